// Sessions, wake-up and the changing-world simulator under hostile input (issue 36; issue 35,
// cases 7 and 13; docs/RELIABILITY.md "Session states"): a session state whose CRC is right but
// whose values or cross-references are not is one line, exit 1, never a crash; counters that
// leave no room are refused; --skip-steps beyond the rawlog says so; every [WakeUp] key is checked
// whether or not a wake-up happens; a stop request ends a wake-up within a second; budget-simulate
// writes nothing budget-slam refuses, and nothing at all when it does not finish.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <csignal>
#include <fstream>

#include "AppTestUtil.h"
#include "ChildProcess.h"
#include "budget_slam/session/SessionStateFile.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// `text` with its end line's CRC-32 written for what is before it (a state changed by hand
/// whose checksum is right).
std::string withCrc(std::string text) {
  text.resize(text.rfind("end crc32 "));
  char end[32];
  std::snprintf(end, sizeof end, "end crc32 %08lx\n",
                crc32_z(0L, reinterpret_cast<const Bytef*>(text.data()), text.size()));
  return text + end;
}

/// The values of the field declared by line `decl` ("ints landmark_ids 63": the count last; the
/// values on the lines below it), changed by `edit` and written back on one line.
std::string editValues(
    std::string text, const std::string& decl,
    const std::function<std::vector<std::string>(std::vector<std::string>)>& edit) {
  const auto at = text.find("\n" + decl + "\n");
  EXPECT_NE(at, std::string::npos) << decl;
  if (at == std::string::npos) return text;
  const std::size_t n = std::stoul(decl.substr(decl.rfind(' ') + 1));
  const auto b = at + decl.size() + 2;
  std::vector<std::string> values;
  std::size_t e = b;
  while (values.size() < n && e < text.size()) {
    const auto eol = text.find('\n', e);
    std::istringstream in(text.substr(e, eol - e));
    for (std::string v; in >> v;) values.push_back(v);
    e = eol + 1;
  }
  values = edit(values);
  std::string line;
  for (const auto& v : values) line += (line.empty() ? "" : " ") + v;
  return text.replace(b, e - b, line + "\n");
}

/// The declaration line of field `name` in `text` ("ints entry_ids 12").
std::string declOf(const std::string& text, const std::string& type, const std::string& name) {
  const auto at = text.find("\n" + type + " " + name + " ");
  EXPECT_NE(at, std::string::npos) << name;
  if (at == std::string::npos) return "";
  return text.substr(at + 1, text.find('\n', at + 1) - at - 1);
}

std::string replacedOnce(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// A first session of the demo under localization-information (cap 10) with place-coverage and
/// random as shadows, whose state the tests change: made once a process.
struct Saved {
  fs::path dir;
  std::string text;
  std::vector<std::string> args(const fs::path& out) const {
    return {"run",        "-c",
            kMrptIni,     "-i",
            kDemo,        "-o",
            out.string(), "--quiet",
            "--reducer",  "localization-information",
            "--cap",      "10",
            "--set",      "LandmarkBudget.shadow_reducers=place-coverage,random"};
  }
};

const Saved& saved() {
  static const Saved s = [] {
    Saved r;
    r.dir = freshDir("hostile_sessions_" + std::to_string(::getpid()));
    const auto a = runApp(plus(r.args(r.dir / "a"), {"--max-steps", "120"}));
    EXPECT_EQ(a.exit_code, 0) << a.err;
    r.text = slurp(r.dir / "a" / "session_state.txt");
    return r;
  }();
  return s;
}

/// Resumes the saved session from a copy whose state is `text`: exit 1 and one error line
/// holding `expected`, and no output folder made.
void expectRefused(const std::string& name, const std::string& text, const std::string& expected) {
  const auto d = freshDir("hostile_state_" + name);
  fs::create_directories(d / "a");
  std::ofstream(d / "a" / "session_state.txt", std::ios::binary) << text;
  const auto r = runApp(plus(saved().args(d / "out"), {"--resume", (d / "a").string()}));
  EXPECT_EQ(r.exit_code, 1) << name << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << name << ": " << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << name << ": " << r.err;
  // The reader's errors come before the output folder; an owner's section is read once the run
  // has its folder, whose summary.json then says why and no step was run.
  if (fs::exists(d / "out")) {
    const auto s = readJson(d / "out" / "summary.json");
    EXPECT_EQ(s["status"], "failed") << name;
    EXPECT_NE(s["error"].get<std::string>().find(expected), std::string::npos) << name;
    EXPECT_FALSE(fs::exists(d / "out" / "session_state.txt")) << name;
  }
}

// Case 2: the localization-information block's cross-references, each wrong with a right CRC,
// killed the resumed run (SIGSEGV in LocalizationInformationReducer::loss at its first drop).
TEST(HostileSessions, CrossReferencesOfTheLocalizationInformationBlock) {
  const std::string& t = saved().text;
  ASSERT_FALSE(t.empty());
  // The state as written resumes.
  {
    const auto d = freshDir("hostile_state_as_written");
    const auto r = runApp(plus(saved().args(d), {"--resume", (saved().dir / "a").string()}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string entries = declOf(t, "ints", "entry_ids");
  const std::string landmarks = declOf(t, "ints", "landmark_ids");
  // An entry id of 2^63 - 1.
  expectRefused("entry_max",
                withCrc(editValues(t, entries,
                                   [](auto v) {
                                     v.back() = "9223372036854775807";
                                     return v;
                                   })),
                "section 'reducer.localization-information'");
  // The landmark ids shifted by one.
  expectRefused("landmarks_shifted",
                withCrc(editValues(t, landmarks,
                                   [](auto v) {
                                     for (auto& x : v) x = std::to_string(std::stoll(x) + 1);
                                     return v;
                                   })),
                "section 'reducer.localization-information'");
  // An entry of a landmark the state does not hold, in order (the id before the first one).
  expectRefused("entry_unknown",
                withCrc(editValues(t, entries,
                                   [](auto v) {
                                     v.front() = std::to_string(std::stoll(v.front()) - 1);
                                     return v;
                                   })),
                "section 'reducer.localization-information'");
  // Every place's entries in reverse order (the lookups assume increasing ids).
  expectRefused("entries_reversed",
                withCrc(editValues(t, entries,
                                   [](auto v) {
                                     std::reverse(v.begin(), v.end());
                                     return v;
                                   })),
                "section 'reducer.localization-information'");
  // A landmark's places in reverse order along with the landmarks: each lists the other's.
  expectRefused("landmarks_reversed",
                withCrc(editValues(t, landmarks,
                                   [](auto v) {
                                     std::reverse(v.begin(), v.end());
                                     return v;
                                   })),
                "section 'reducer.localization-information'");
}

// The place-coverage shadow's cross-references (forgetPlace followed them without looking).
TEST(HostileSessions, CrossReferencesOfThePlaceCoverageBlock) {
  const std::string& t = saved().text;
  const std::string tracks = declOf(t, "ints", "track_ids");
  expectRefused("tracks_shifted",
                withCrc(editValues(t, tracks,
                                   [](auto v) {
                                     for (auto& x : v) x = std::to_string(std::stoll(x) + 1);
                                     return v;
                                   })),
                "section 'reducer.place-coverage'");
}

// Case 3: counters that leave no room for the steps to come.
TEST(HostileSessions, CountersThatOverflowAreRefused) {
  const std::string& t = saved().text;
  expectRefused("sessions_max",
                withCrc(replacedOnce(t, "int sessions 1\n", "int sessions 9223372036854775807\n")),
                "field 'sessions': 9223372036854775807 is out of range");
  const std::string next = declOf(t, "int", "next_step");
  expectRefused("next_step_max",
                withCrc(replacedOnce(t, next + "\n", "int next_step 9223372036854775800\n")),
                "field 'next_step': 9223372036854775800 is out of range");
}

// Case 6: a generator state longer than any real one.
TEST(HostileSessions, ALongerRandomGeneratorStateIsRefused) {
  const std::string& t = saved().text;
  const auto at = t.find("text rng_state ");
  ASSERT_NE(at, std::string::npos);
  const auto eol = t.find('\n', at);
  std::string longer = t;
  longer.insert(eol, " 12345 678");
  expectRefused("rng_longer", withCrc(longer),
                "field 'rng_state': not the state of a mt19937_64 generator");
}

// Case 7: a state over its own cap is not one the program wrote (its first step dropped 1,950
// landmarks, the shadow consulted at each, for minutes).
TEST(HostileSessions, AMapOverTheSavedCapIsRefused) {
  session::SessionState s =
      session::readSessionState((saved().dir / "a" / "session_state.txt").string());
  const std::size_t n = s.map.landmarks.size(), more = 5;
  ASSERT_LE(n, 10u);
  auto& map = s.map;
  Eigen::MatrixXd cov = Eigen::MatrixXd::Identity(2 * (n + more), 2 * (n + more));
  cov.topLeftCorner(2 * n, 2 * n) = map.covariance;
  map.covariance = cov;
  for (std::size_t k = 0; k < more; ++k) {
    LandmarkView v = map.landmarks.front();
    v.id = 100000 + static_cast<LandmarkId>(k);
    v.mean += Eigen::Vector2d(100.0 + k, 0);
    map.landmarks.push_back(v);
  }
  if (s.robot) {
    Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, 2 * (n + more));
    cross.leftCols(2 * n) = s.robot->cross_covariance;
    s.robot->cross_covariance = cross;
  }
  expectRefused("over_cap", session::formatSessionState(s),
                std::to_string(n + more) +
                    " landmarks, more than the saved [LandmarkBudget] max_landmarks = 10");
}

// Case 4: --skip-steps that leaves no step to run (the demo has 249 steps), with and without
// --resume.
TEST(HostileSessions, SkipStepsBeyondTheRawlogIsOneLine) {
  const auto d = freshDir("hostile_skip");
  for (const std::string& n : {"100000", "249"}) {
    const auto r = runApp(plus(saved().args(d / ("plain_" + n)), {"--skip-steps", n}));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(isOneLine(
        r.err, Said::Error,
        "--skip-steps " + n + ": rawlog '" + kDemo + "' holds 249 steps; none " + "is left to run"))
        << r.err;
    const auto s = readJson(d / ("plain_" + n) / "summary.json");
    EXPECT_EQ(s["status"], "failed");
  }
  const auto resumed =
      runApp(plus(saved().args(d / "resumed"),
                  {"--resume", (saved().dir / "a").string(), "--skip-steps", "100000"}));
  EXPECT_EQ(resumed.exit_code, 1) << resumed.err;
  EXPECT_NE(resumed.err.find("none is left to run"), std::string::npos) << resumed.err;
  for (const std::string& n : {"9223372036854775807", "18446744073709551615"}) {
    const auto r = runApp(plus(saved().args(d / "huge"), {"--skip-steps", n}));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--skip-steps '" + n + "': more steps than a rawlog can hold"),
              std::string::npos)
        << r.err;
  }
}

// Case 5: [WakeUp] keys are checked by run, localize and run --resume whether or not a wake-up
// happens.
TEST(HostileSessions, WakeUpKeysAreCheckedWithoutAWakeUp) {
  const auto d = freshDir("hostile_wake_keys");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"WakeUp.max_hypotheses=0", "[WakeUp] max_hypotheses"},
      {"WakeUp.correspondence=bogus", "[WakeUp] correspondence"},
      {"WakeUp.gate_chi2=-1", "[WakeUp] gate_chi2"},
      {"WakeUp.max_steps=nan", "[WakeUp] max_steps"}};
  for (const auto& [set, key] : bad) {
    const auto run = runApp(plus(saved().args(d / "run"), {"--set", set}));
    EXPECT_NE(run.exit_code, 0) << set;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find(key), std::string::npos) << run.err;
    const auto resumed = runApp(plus(saved().args(d / "resumed"),
                                     {"--resume", (saved().dir / "a").string(), "--set", set}));
    EXPECT_NE(resumed.exit_code, 0) << set;
    EXPECT_NE(resumed.err.find(key), std::string::npos) << resumed.err;
    const auto loc =
        runApp({"localize", "-c", kMrptIni, "-i", kDemo, "--map", (saved().dir / "a").string(),
                "-o", (d / "loc").string(), "--quiet", "--start-pose", "0,0,0", "--set", set});
    EXPECT_NE(loc.exit_code, 0) << set;
    EXPECT_NE(loc.err.find(key), std::string::npos) << loc.err;
  }
}

/// Starts `args` of budget-slam, sends SIGTERM after `after_s`, and returns how it ended and the
/// seconds from the signal to its end (at most 60: then SIGKILL).
struct Stopped {
  int code = -1;
  double seconds = 0;
  std::string err;
};
Stopped stopAfter(const std::vector<std::string>& args, const fs::path& dir, double after_s) {
  fs::create_directories(dir);
  const pid_t pid = startChild(binary("budget-slam"), args, (dir / "err").string());
  ::usleep(static_cast<useconds_t>(after_s * 1e6));
  Stopped s;
  int status = 0;
  if (::waitpid(pid, &status, WNOHANG) == pid) {  // ended before the signal: say so
    s.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    s.seconds = -1;
    s.err = slurp(dir / "err");
    return s;
  }
  const auto t0 = std::chrono::steady_clock::now();
  ::kill(pid, SIGTERM);
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(60)) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    ::usleep(10000);
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  s.err = slurp(dir / "err");
  return s;
}

// Case 1: a wake-up that searches for long (every step's readings kept, a landmark count no pose
// reaches) ends within a second of SIGTERM, exit 130 and status interrupted, for localize
// --wake-up and run --resume --wake-up.
TEST(HostileSessions, AStopEndsAWakeUpWithinASecond) {
  const auto d = freshDir("hostile_wake_stop");
  const auto map = d / "map";
  ASSERT_EQ(runApp({"run", "-c", kRoot + "/config.ini", "-i", kRoot + "/rawlogs/clusters.rawlog",
                    "-o", map.string(), "--quiet", "--cap", "40", "--reducer", "oldest"})
                .exit_code,
            0);
  const std::vector<std::string> search = {"--set", "WakeUp.correspondence=search",
                                           "--set", "WakeUp.max_steps=100000",
                                           "--set", "WakeUp.search_min_landmarks=100000"};
  const std::string revisit = kRoot + "/rawlogs/clusters_revisit.rawlog";
  const auto loc =
      stopAfter(plus({"localize", "-c", kRoot + "/config.ini", "-i", revisit, "--map", map.string(),
                      "-o", (d / "loc").string(), "--quiet", "--wake-up"},
                     search),
                d / "loc_run", 3);
  ASSERT_GE(loc.seconds, 0) << "the wake-up ended before the signal: " << loc.err;
  EXPECT_EQ(loc.code, 130) << loc.err;
  EXPECT_LT(loc.seconds, 1.0) << loc.err;
  EXPECT_EQ(readJson(d / "loc" / "summary.json")["status"], "interrupted");

  const auto res = stopAfter(
      plus({"run", "-c", kRoot + "/config.ini", "-i", revisit, "-o", (d / "res").string(),
            "--quiet", "--cap", "40", "--reducer", "oldest", "--resume", map.string(), "--wake-up"},
           search),
      d / "res_run", 3);
  ASSERT_GE(res.seconds, 0) << "the wake-up ended before the signal: " << res.err;
  EXPECT_EQ(res.code, 130) << res.err;
  EXPECT_LT(res.seconds, 1.0) << res.err;
  EXPECT_TRUE(isOneLine(res.err, Said::Interrupted,
                        "interrupted by SIGTERM while waking up on the saved map"))
      << res.err;
  EXPECT_FALSE(fs::exists(d / "res"));
}

// Issue 35, case 7: a rawlog named with a newline runs, its session state holds the name, and
// the next session resumes from it.
TEST(HostileSessions, ARawlogNamedWithANewlineRunsAndResumes) {
  const auto d = freshDir("hostile_newline_rawlog");
  fs::create_directories(d);
  const fs::path rawlog = d / "demo\nnext \\ line.rawlog";
  fs::copy_file(kDemo, rawlog);
  const auto a = runApp({"run", "-c", kMrptIni, "-i", rawlog.string(), "-o", (d / "a").string(),
                         "--quiet", "--max-steps", "100"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto s = session::readSessionState((d / "a" / "session_state.txt").string());
  EXPECT_EQ(s.header.rawlog, rawlog.string());
  const auto b = runApp({"run", "-c", kMrptIni, "-i", rawlog.string(), "-o", (d / "b").string(),
                         "--quiet", "--resume", (d / "a").string(), "--skip-steps", "100"});
  EXPECT_EQ(b.exit_code, 0) << b.err;
}

/// budget-simulate with `args`, output in `dir`: the exit code and stderr.
Process simulate(const fs::path& dir, const std::string& args) {
  fs::create_directories(dir);
  return runBinary("budget-simulate' " + args, dir);
}

// Issue 35, case 13: noise values budget-simulate took and budget-slam then refused. Each is
// either refused by the simulator (exit 2, one line) or written so that budget-slam runs on it.
TEST(HostileSessions, TheSimulatorWritesNothingItsSiblingRefuses) {
  const auto d = freshDir("hostile_simulate_noise");
  const std::vector<std::string> runs = {"--zero-noise", "--sensor-std-range 0",
                                         "--sensor-std-yaw-deg 1e-320", "--odo-std-xy 0"};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto dir = d / std::to_string(i);
    const auto p = simulate(dir, "-s rooms --laps 1 -o sim.rawlog " + runs[i]);
    ASSERT_EQ(p.exit_code, 0) << runs[i] << ": " << p.err;
    const auto r = runApp({"run", "-c", kRoot + "/config.ini", "-i", (dir / "sim.rawlog").string(),
                           "-o", (dir / "out").string(), "--quiet", "--max-steps", "50"});
    EXPECT_EQ(r.exit_code, 0) << runs[i] << ": " << r.err;
  }
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"--sensor-std-range 1e308", "--sensor-std-range 1e+308: must be at most 10000 m"},
      {"--odo-std-xy 1e308", "--odo-std-xy 1e+308: must be at most 100 m"},
      {"--odo-std-yaw-deg 1e308", "--odo-std-yaw-deg 1e+308: must be at most 72 deg"},
      {"--sensor-std-yaw-deg 1e308", "--sensor-std-yaw-deg 1e+308: must be at most 360 deg"}};
  for (const auto& [flag, message] : refused) {
    const auto dir = d / "refused";
    const auto p = simulate(dir, "-s rooms --laps 1 -o sim.rawlog " + flag);
    EXPECT_EQ(p.exit_code, 2) << flag << ": " << p.err;
    EXPECT_EQ(std::count(p.err.begin(), p.err.end(), '\n'), 1) << p.err;
    EXPECT_NE(p.err.find(message), std::string::npos) << p.err;
    EXPECT_FALSE(fs::exists(dir / "sim.rawlog"));
  }
}

// Case 8: the sessions' options, a closed stdout, and a stop that leaves no finished session.
TEST(HostileSessions, SimulatorSessionsOptionsAndStops) {
  const auto d = freshDir("hostile_simulate_sessions");
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"--change ''", "--change '': an empty value"},
      {"--move-distance ''", "--move-distance '': an empty value"},
      {"--change-split 1e308:1e308:1e308", "--change-split: each share must be a number in"},
      {"--move-distance 1e308", "--move-distance 1e+308: puts landmark"},
      {"--move-distance 1e6", "--move-distance 1e+06: puts landmark"}};
  for (const auto& [flag, message] : refused) {
    const auto dir = d / "refused";
    const auto p = simulate(dir, "-s rooms --sessions 3 --change 0.5 -o life.rawlog " + flag);
    EXPECT_EQ(p.exit_code, 2) << flag << ": " << p.err;
    EXPECT_EQ(std::count(p.err.begin(), p.err.end(), '\n'), 1) << p.err;
    EXPECT_NE(p.err.find(message), std::string::npos) << flag << ": " << p.err;
    EXPECT_TRUE(fs::is_empty(dir)) << flag;
  }
  // A closed stdout: exit 1, as the single-rawlog mode.
  fs::create_directories(d / "closed");
  const std::string closed = "cd '" + (d / "closed").string() + "' && '" +
                             binary("budget-simulate") +
                             "' -s rooms --sessions 2 -o life.rawlog >&- 2> err.txt";
  const int status = std::system(closed.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << slurp(d / "closed" / "err.txt");

  // SIGINT while the sessions are written: exit 130 and no file of the series left.
  const auto dir = d / "stopped";
  fs::create_directories(dir);
  const pid_t pid =
      startChild(binary("budget-simulate"),
                 {"-s", "park", "--sessions", "200", "-o", (dir / "life.rawlog").string()},
                 (d / "stopped_err").string());
  // Wait for the first finished session, then stop.
  for (int i = 0; i < 600 && !fs::exists(dir / "life_s002.rawlog"); ++i) ::usleep(50000);
  ::kill(pid, SIGINT);
  const auto e = waitChild(pid);
  EXPECT_EQ(e.code, 130) << slurp(d / "stopped_err");
  std::vector<std::string> left;
  for (const auto& f : fs::directory_iterator(dir)) left.push_back(f.path().filename().string());
  EXPECT_TRUE(left.empty()) << left.size() << " files left, e.g. " << left.front();
}

}  // namespace
