// Who owns an output folder (docs/RELIABILITY.md "Two runs into one folder", "A failed start"):
// a second run into a folder another run is writing is refused with one line naming the
// holder's process id (issue 23, case 6), compare holds its run folders the same way, and a run
// that failed before its first step leaves nothing that blocks the corrected command, whose
// message names where the bad value came from (issue 25, point 3).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include "AppTestUtil.h"
#include "budget_slam/report/FolderLock.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

std::set<std::string> namesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

std::size_t wholeLines(const fs::path& p) {
  const std::string s = slurp(p);
  EXPECT_TRUE(s.empty() || s.back() == '\n') << p;
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

/// A process running `args` in-process that stops at its step `pause_at` (or, with pause_at < 0,
/// at its end phase) until release() is called; started() returns once it got there.
class PausedRun {
 public:
  PausedRun(std::vector<std::string> args, int pause_at) {
    int ready[2], go[2];
    if (::pipe(ready) != 0 || ::pipe(go) != 0) throw std::runtime_error("pipe");
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(ready[0]);
      ::close(go[1]);
      const auto hold = [&] {
        const char c = 'r';
        if (::write(ready[1], &c, 1) != 1) ::_exit(90);
        char g;
        if (::read(go[0], &g, 1) != 1) ::_exit(91);
      };
      const auto r = runApp(args, [&](app::BudgetSlamApp& a) {
        if (pause_at >= 0)
          a.on_step = [&, pause_at](StepIndex s) {
            if (static_cast<int>(s) == pause_at) hold();
          };
        else
          a.on_end_phase = [&, done = false]() mutable {
            if (!done) done = true, hold();
          };
      });
      std::fflush(nullptr);
      ::_exit(r.exit_code);
    }
    ::close(ready[1]);
    ::close(go[0]);
    ready_ = ready[0];
    go_ = go[1];
  }
  ~PausedRun() {
    if (pid_ > 0) {
      release();
      wait();
    }
  }
  /// Waits until the run holds at its pause point; false when it ended first.
  bool started() {
    char c;
    return ::read(ready_, &c, 1) == 1;
  }
  void release() {
    if (go_ >= 0) {
      const char c = 'g';
      if (::write(go_, &c, 1) != 1) {
      }
      ::close(go_);
      go_ = -1;
    }
  }
  /// The exit code (-signal when killed).
  int wait() {
    if (pid_ <= 0) return code_;
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -pid_;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    return code_;
  }
  pid_t pid() const { return pid_ > 0 ? pid_ : -pid_; }

 private:
  pid_t pid_ = 0;
  int ready_ = -1, go_ = -1, code_ = 0;
};

std::string inUse(const fs::path& folder, pid_t holder) {
  return "output folder '" + folder.string() + "' is in use by process " + std::to_string(holder) +
         " (it holds " + (folder / report::FolderLock::kFileName).string() +
         "); wait for it to end or give another output folder";
}

}  // namespace

// Issue 23, case 6: a second run into a folder another run is writing.
TEST(Ownership, ASecondRunIntoAFolderInUseIsRefusedNamingTheHolder) {
  const auto out = freshDir("two_runs");
  const std::vector<std::string> args = {"run",       "-c",     kMrptIni,     "-i",
                                         kDemo,       "-o",     out.string(), "--quiet",
                                         "--reducer", "oldest", "--cap",      "10"};
  PausedRun first(args, 100);
  ASSERT_TRUE(first.started());
  for (const bool force : {false, true}) {
    SCOPED_TRACE(force ? "--force" : "no --force");
    auto second_args = args;
    if (force) second_args.push_back("--force");
    const auto second = runApp(second_args);
    EXPECT_EQ(second.exit_code, 1);
    EXPECT_TRUE(isErrorLine(second.err, inUse(out, first.pid())));
  }
  // Nothing of the second run: no earlier_run_ folder, no summary yet.
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  for (const auto& n : namesIn(out)) EXPECT_EQ(n.rfind("earlier_run_", 0), std::string::npos) << n;
  first.release();
  ASSERT_EQ(first.wait(), 0);
  // The first run's outputs, whole and one run's: steps.csv, trajectory.tum and summary agree.
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "ok");
  const std::size_t steps = wholeLines(out / "steps.csv") - 1;
  EXPECT_EQ(s["counts"]["steps"], steps);
  EXPECT_EQ(wholeLines(out / "trajectory.tum"), steps);
  // The lock went with its holder.
  EXPECT_FALSE(fs::exists(out / report::FolderLock::kFileName));
}

// compare holds each of its run folders: a run into one of them is refused too.
TEST(Ownership, CompareHoldsItsRunFolders) {
  const auto out = freshDir("compare_held");
  PausedRun compare(
      {"compare", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet", "--reducers",
       "oldest", "--cap", "10", "--threads", "1", "--set", "MappingApplication.max_steps=40"},
      -1);
  ASSERT_TRUE(compare.started());
  const auto r = runApp(
      {"run", "-c", kMrptIni, "-i", kDemo, "-o", (out / "oldest").string(), "--quiet", "--force"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, inUse(out / "oldest", compare.pid())));
  const auto top = runApp({"compare", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet",
                           "--force", "--reducers", "oldest"});
  EXPECT_EQ(top.exit_code, 1);
  EXPECT_TRUE(isErrorLine(top.err, inUse(out, compare.pid())));
  compare.release();
  EXPECT_EQ(compare.wait(), 0);
  EXPECT_EQ(readCsv(out / "comparison.csv").size(), 2u);
  EXPECT_EQ(readJson(out / "oldest" / "summary.json")["counts"]["steps"], 40);
}

// A lock file left by a process that was killed (SIGKILL: no clean-up) holds nothing.
TEST(Ownership, AStaleLockFileDoesNotBlock) {
  const auto out = freshDir("stale_lock");
  fs::create_directories(out);
  std::ofstream(out / report::FolderLock::kFileName) << "999999\n";
  const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet", "--set",
                         "MappingApplication.max_steps=20"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / report::FolderLock::kFileName));
}

// Issue 25, point 3: the failed start does not block the corrected command, and the message
// names where the value came from.
TEST(Ownership, AFailedStartDoesNotBlockTheRetry) {
  const auto out = freshDir("failed_start");
  const std::vector<std::string> base = {"run", "-c", kMrptIni,     "-i",
                                         kDemo, "-o", out.string(), "--quiet"};
  auto args = base;
  args.insert(args.end(), {"--set", "LandmarkBudget.max_landmarks=abc"});
  const auto bad = runApp(args);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(isErrorLine(bad.err,
                          "--set 'LandmarkBudget.max_landmarks=abc': [LandmarkBudget] "
                          "max_landmarks = 'abc': not an integer (or none for no cap)"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["started"], false);

  args = base;
  args.insert(args.end(), {"--set", "LandmarkBudget.max_landmarks=10", "--set",
                           "MappingApplication.max_steps=30"});
  const auto good = runApp(args);
  ASSERT_EQ(good.exit_code, 0) << good.err;
  EXPECT_EQ(good.err, "");  // no note of an earlier run: it made nothing worth keeping
  EXPECT_EQ(readJson(out / "summary.json")["status"], "ok");
  EXPECT_EQ(readJson(out / "summary.json")["started"], true);
  for (const auto& n : namesIn(out)) EXPECT_EQ(n.rfind("earlier_run_", 0), std::string::npos) << n;

  // A run that failed later (a started one) still needs --force: its files are kept.
  const auto again = runApp(args);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_TRUE(isErrorLine(again.err, "output folder '" + out.string() +
                                         "' is not empty (use --force to write into it)"));
}

TEST(Ownership, AFailedStartOfCompareAndLocalizeDoesNotBlockEither) {
  const auto out = freshDir("failed_start_compare");
  const auto compare = [&](const std::string& rawlog) {
    return runApp({"compare", "-c", kMrptIni, "-i", rawlog, "-o", out.string(), "--quiet",
                   "--reducers", "oldest", "--cap", "10", "--set",
                   "MappingApplication.max_steps=20"});
  };
  const auto bad = compare((out.parent_path() / "missing.rawlog").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(readJson(out / "summary.json")["started"], false);
  const auto good = compare(kDemo);
  EXPECT_EQ(good.exit_code, 0) << good.err;

  // localize: a missing map folder fails before the first step.
  const auto loc = freshDir("failed_start_localize");
  const auto localize = [&](const fs::path& map) {
    return runApp({"localize", "-c", kMrptIni, "-i", kDemo, "-o", loc.string(), "--quiet", "--map",
                   map.string(), "--set", "Localization.max_steps=10"});
  };
  const auto missing = localize(out / "no_such_run");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(readJson(loc / "summary.json")["started"], false);
  const auto ok = localize(out / "oldest");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// The value's origin in messages: the sidecar ini of the rawlog, not the -c file.
TEST(Ownership, AValueFromTheSidecarIsNamedWithTheSidecar) {
  const auto dir = freshDir("sidecar_origin");
  fs::create_directories(dir);
  fs::copy_file(kDemo, dir / "demo.rawlog");
  std::ofstream(dir / "demo.ini") << "[RangeBearingKFSLAM]\nstd_sensor_range = 0\n";
  const auto out = dir / "out";
  const auto r = runApp(
      {"run", "-c", kMrptIni, "-i", (dir / "demo.rawlog").string(), "-o", out.string(), "--quiet"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(
      isErrorLine(r.err, (dir / "demo.ini").string() +
                             ": [RangeBearingKFSLAM] std_sensor_range = 0: must be > 0 (a standard "
                             "deviation)"));
}
