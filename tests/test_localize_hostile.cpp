// `budget-slam localize` on a hostile map folder and command line (issue 23, case 4;
// docs/RELIABILITY.md "Map folders"): absurd values are refused with one line naming the file and
// the key or line, a signal ends it, `--start-pose ''` is a bad command line.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>

#include "AppTestUtil.h"
#include "ChildProcess.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// A map folder: a run of the demo (cap 15), made once a process (ctest runs the tests of this
/// file in parallel processes).
const fs::path& demoMap() {
  static const fs::path map = [] {
    const auto d = freshDir("localize_hostile_map_" + std::to_string(::getpid()));
    const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", d.string(), "--quiet",
                           "--reducer", "oldest", "--cap", "15"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d;
  }();
  return map;
}

/// A copy of the demo map whose summary.json gets `edit`.
fs::path editedMap(const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
  const auto d = freshDir(name);
  fs::create_directories(d);
  fs::copy_file(demoMap() / "landmarks.csv", d / "landmarks.csv");
  auto j = readJson(demoMap() / "summary.json");
  edit(j);
  std::ofstream(d / "summary.json") << j.dump(2);
  return d;
}

struct Exit {
  int code = -1;
  std::string err;
  double seconds = 0;
};

/// The executable, with issue 23's limits (a hang is a failure, not a stuck test).
Exit localizeBinary(const fs::path& map, const fs::path& out,
                    const std::vector<std::string>& extra = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> args = {"localize", "-c",         kMrptIni, "-i",         kDemo,
                                   "--map",    map.string(), "-o",     out.string(), "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = runChild(binary("budget-slam"), args, out.string() + ".err", hostileLimits);
  return {r.code, slurp(out.string() + ".err"),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

}  // namespace

TEST(LocalizeHostile, AnAbsurdAlignmentIsRefusedNamingFileAndKey) {
  for (const char* key : {"x", "y", "yaw"}) {
    SCOPED_TRACE(key);
    const auto map = editedMap(std::string("absurd_alignment_") + key, [&](nlohmann::json& j) {
      j["ground_truth"]["map_alignment"][key] = 1e308;
    });
    const auto out = freshDir(std::string("absurd_alignment_out_") + key);
    const auto r = localizeBinary(map, out);
    EXPECT_EQ(r.code, 1) << r.err;
    const std::string unit = std::string(key) == "yaw" ? "12.5664 rad" : "1e+06 m";
    EXPECT_TRUE(
        isErrorLine(r.err, (map / "summary.json").string() + ": ground_truth.map_alignment." + key +
                               " = 1e+308 is out of range (at most " + unit + " either way)"));
    EXPECT_LT(r.seconds, 30);
    EXPECT_EQ(readJson(out / "summary.json")["status"], "failed");
  }
}

TEST(LocalizeHostile, AbsurdLandmarksAndDeepJsonAreRefused) {
  const auto map = freshDir("absurd_landmark");
  fs::create_directories(map);
  std::string csv = slurp(demoMap() / "landmarks.csv");
  const auto row = csv.find('\n') + 1;
  const auto comma = csv.find(',', row);
  csv.replace(comma + 1, csv.find(',', comma + 1) - comma - 1, "1e300");  // x of the first row
  std::ofstream(map / "landmarks.csv") << csv;
  auto r = localizeBinary(map, freshDir("absurd_landmark_out"), {"--start-pose", "0,0,0"});
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(isErrorLine(r.err, (map / "landmarks.csv").string() +
                                     ":2: x = 1e300 is out of range (at most 1e+06 either way)"));

  const auto deep = freshDir("deep_summary");
  fs::create_directories(deep);
  fs::copy_file(demoMap() / "landmarks.csv", deep / "landmarks.csv");
  std::ofstream(deep / "summary.json") << std::string(100000, '[') << std::string(100000, ']');
  r = localizeBinary(deep, freshDir("deep_summary_out"));
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(isErrorLine(r.err, (deep / "summary.json").string() +
                                     ": nested deeper than 16 levels, not a budget-slam summary"));
}

TEST(LocalizeHostile, AnEmptyOrAbsurdStartPoseIsABadCommandLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "--start-pose '': expected x,y,yaw (metres, metres, degrees)"},
      {"1,2", "--start-pose '1,2': expected x,y,yaw (metres, metres, degrees)"},
      {"1,2,3,", "--start-pose '1,2,3,': expected x,y,yaw (metres, metres, degrees)"},
      {"1e308,0,0", "--start-pose '1e308,0,0': x and y must be within 1e6 m of the map's origin"},
      {"0,0,1e308", "--start-pose '0,0,1e308': yaw must be within 720 degrees"}};
  for (const auto& [pose, message] : cases) {
    SCOPED_TRACE(pose);
    const auto out = freshDir("start_pose");
    const auto r = runApp({"localize", "-c", kMrptIni, "-i", kDemo, "--map", demoMap().string(),
                           "-o", out.string(), "--start-pose", pose});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(isOneLine(r.err, Said::CommandLine, message + "; see budget-slam localize --help"));
    EXPECT_FALSE(fs::exists(out));
  }
}

// Ctrl-C, and SIGTERM after it, end a localization: one line, exit 130, its outputs.
TEST(LocalizeHostile, SignalsEndIt) {
  const auto out = freshDir("localize_signals");
  const auto r = runApp({"localize", "-c", kMrptIni, "-i", kDemo, "--map", demoMap().string(), "-o",
                         out.string(), "--quiet"},
                        [](app::BudgetSlamApp& a) {
                          a.on_step = [](StepIndex s) {
                            if (s == 20) std::raise(SIGINT), std::raise(SIGTERM);
                          };
                        });
  EXPECT_EQ(r.exit_code, 130);
  EXPECT_TRUE(isOneLine(r.err, Said::Interrupted, "interrupted by Ctrl-C after step 20"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["counts"]["steps"], 21);
}

// Case 4, a hostile map folder that never ends: its summary.json a FIFO nobody writes (reading
// it would block for ever) is refused at once; and Ctrl-C then SIGTERM 50 ms later, sent to the
// executable while it waits for its -c file (a FIFO too), end it with exit 130 and one line,
// never the default action.
TEST(LocalizeHostile, AFolderThatNeverEndsOrTwoSignalsEndItAtOnce) {
  const auto map = freshDir("fifo_summary");
  fs::create_directories(map);
  fs::copy_file(demoMap() / "landmarks.csv", map / "landmarks.csv");
  ASSERT_EQ(::mkfifo((map / "summary.json").c_str(), 0644), 0);
  auto r = localizeBinary(map, freshDir("fifo_summary_out"));
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(isErrorLine(r.err, (map / "summary.json").string() + ": not a regular file"));
  EXPECT_LT(r.seconds, 30);

  const auto dir = freshDir("localize_signals_at_start");
  fs::create_directories(dir);
  const auto fifo = dir / "config.ini";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const auto out = dir / "out";
  const pid_t pid = startChild(binary("budget-slam"),
                               {"localize", "-c", fifo.string(), "-i", kDemo, "--map",
                                demoMap().string(), "-o", out.string(), "--quiet"},
                               (dir / "err").string(), hostileLimits);
  ASSERT_GT(pid, 0);
  EXPECT_TRUE(waitUntilBlockedOnFifo(pid));  // blocked opening its -c file
  ::kill(pid, SIGINT);
  ::usleep(50000);
  ::kill(pid, SIGTERM);
  const auto e = feedFifoAndWait(pid, fifo.string(), slurp(kMrptIni));
  const std::string err = slurp(dir / "err");
  ASSERT_FALSE(e.signaled()) << "killed by signal " << -e.code << ": " << err;
  EXPECT_EQ(e.code, 130);
  EXPECT_TRUE(isOneLine(err, Said::Interrupted, "interrupted by Ctrl-C before the first step"));
  EXPECT_EQ(readJson(out / "summary.json")["status"], "interrupted");
}
