// Resource limits and signals (issue 23, cases 5 and 7; docs/RELIABILITY.md): a full disk, few
// file descriptors, an address-space limit, a closed stdout, a second signal. Each ends with one
// line on stderr, a defined exit code and a valid summary.json (or, where none could be written,
// the line says why); never a signal, an abort or MRPT's own messages.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "AppTestUtil.h"
#include "ChildProcess.h"
#include "budget_slam/core/FileWrite.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kBin = binary("budget-slam");

struct Exit {
  int code = -1;    ///< exit code, or -signal
  std::string err;  ///< everything written on fd 2, MRPT's own lines included
};

/// The budget-slam executable with `args`, stderr kept, under `limit` (set in the child).
Exit runBinary(const std::vector<std::string>& args, const fs::path& err_file,
               const std::function<void()>& limit = {}, int stdout_fd = -1) {
  const auto r = runChild(kBin, args, err_file.string(), limit, stdout_fd);
  return {r.code, slurp(err_file)};
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

/// One line on stderr for a failure (compare: one a run that failed, and one for its own files:
/// at most `max_lines`), and summary.json valid and saying failed, or the line saying why
/// summary.json could not be written.
void expectOneLineAndSummary(const Exit& r, const fs::path& out, int max_lines = 1) {
  ASSERT_GE(r.code, 0) << "killed by signal " << -r.code << "; stderr: " << r.err;
  if (r.code == 0) {
    EXPECT_EQ(r.err, "");
  } else {
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_GE(lines(r.err), 1) << r.err;
    EXPECT_LE(lines(r.err), max_lines) << r.err;
    for (std::size_t at = 0, end; (end = r.err.find('\n', at)) != std::string::npos; at = end + 1)
      EXPECT_EQ(r.err.compare(at, 20, "budget-slam: error: "), 0) << r.err;
  }
  EXPECT_EQ(r.err.find("compress_gz"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  if (fs::exists(out / "summary.json")) {
    const auto s = readJson(out / "summary.json");  // throws when not valid JSON
    EXPECT_EQ(s["status"], r.code == 0 ? "ok" : "failed") << r.err;
  } else if (fs::exists(out)) {
    EXPECT_NE(r.err.find("summary.json"), std::string::npos)
        << "no summary.json and the line does not say why: " << r.err;
  }
}

const std::vector<std::string> kRun = {"run",     "-c",        kMrptIni, "-i",    kDemo,
                                       "--quiet", "--reducer", "oldest", "--cap", "10"};

std::vector<std::string> with(std::vector<std::string> args, const fs::path& out) {
  args.push_back("-o");
  args.push_back(out.string());
  return args;
}

}  // namespace

// Case 5: a full disk, made in-process (DiskSpaceForTests: no mount needed), at every size
// from nothing to almost enough; run, compare and localize.
TEST(Limits, AFullDiskLeavesASummaryOrSaysWhyNot) {
  const auto map = freshDir("disk_map");
  ASSERT_EQ(runApp(with(kRun, map)).exit_code, 0);
  const std::vector<std::vector<std::string>> commands = {
      kRun,
      {"compare", "-c", kMrptIni, "-i", kDemo, "--quiet", "--reducers", "mi,oldest", "--cap", "10",
       "--threads", "2", "--set", "MappingApplication.max_steps=60"},
      {"localize", "-c", kMrptIni, "-i", kDemo, "--quiet", "--map", map.string()}};
  for (const auto& command : commands) {
    for (const std::size_t kib : {0, 2, 4, 12, 24, 60, 100, 200}) {
      SCOPED_TRACE(command[0] + " on a disk of " + std::to_string(kib) + " KiB");
      const auto out = freshDir("disk_" + command[0] + "_" + std::to_string(kib));
      AppResult r;
      {
        DiskSpaceForTests disk(kib * 1024);
        r = runApp(with(command, out));
      }
      // compare: mi, oldest and the reference, and its own files.
      expectOneLineAndSummary({r.exit_code, r.err}, out, command[0] == "compare" ? 4 : 1);
      if (r.exit_code != 0) {
        EXPECT_NE(r.err.find("(No space left on device)"), std::string::npos) << r.err;
      }
      // compare: every run folder made has its summary too.
      if (command[0] == "compare" && fs::exists(out)) {
        for (const auto& e : fs::directory_iterator(out)) {
          if (e.is_directory() && fs::exists(e.path() / "config_used.ini")) {
            EXPECT_TRUE(fs::exists(e.path() / "summary.json") ||
                        r.err.find("summary.json") != std::string::npos)
                << e.path() << ": " << r.err;
          }
        }
      }
    }
  }
}

// Case 5: few file descriptors (ulimit -n 5 to 10): one line, a summary, no MRPT message.
TEST(Limits, FewFileDescriptorsGiveOneLineAndASummary) {
  for (const char* command : {"run", "compare"}) {
    for (rlim_t n = 5; n <= 10; ++n) {
      SCOPED_TRACE(std::string(command) + " under ulimit -n " + std::to_string(n));
      const auto out = freshDir(std::string("fds_") + command + std::to_string(n));
      std::vector<std::string> args = kRun;
      if (std::string(command) == "compare")
        args = {"compare",    "-c",
                kMrptIni,     "-i",
                kDemo,        "--quiet",
                "--reducers", "oldest",
                "--cap",      "10",
                "--threads",  "1",
                "--set",      "MappingApplication.max_steps=60"};
      const auto r = runBinary(with(args, out), out.string() + ".err", [n] {
        const rlimit l{n, n};
        ::setrlimit(RLIMIT_NOFILE, &l);
      });
      expectOneLineAndSummary(r, out, std::string(command) == "compare" ? 3 : 1);
    }
  }
}

// Issue 35: compare --threads 3 under 12 to 18 file descriptors. Every run folder made holds a
// summary.json with its own error: the run whose making failed says why in its own folder (it had
// none), the others that they did not start (they carried that run's error as their own).
TEST(Limits, FewFileDescriptorsGiveEveryRunItsOwnSummary) {
  for (rlim_t n = 12; n <= 18; n += 2) {
    SCOPED_TRACE("compare --threads 3 under ulimit -n " + std::to_string(n));
    const auto out = freshDir("fds_threads" + std::to_string(n));
    const auto r = runBinary(
        with({"compare", "-c", kMrptIni, "-i", kDemo, "--quiet", "--reducers", "mi,oldest", "--cap",
              "10", "--threads", "3", "--set", "MappingApplication.max_steps=60"},
             out),
        out.string() + ".err", [n] {
          const rlimit l{n, n};
          ::setrlimit(RLIMIT_NOFILE, &l);
        });
    expectOneLineAndSummary(r, out, 4);
    if (!fs::exists(out / "summary.json")) continue;
    const auto top = readJson(out / "summary.json");
    for (const char* run : {"reference", "mi", "oldest"}) {
      if (!fs::exists(out / run)) continue;
      SCOPED_TRACE(run);
      if (!fs::exists(out / run / "summary.json")) {
        // No descriptor was left even for it: the line says so.
        EXPECT_NE(r.err.find("/" + std::string(run) + "/"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("its summary.json not written either"), std::string::npos) << r.err;
        continue;
      }
      const auto s = readJson(out / run / "summary.json");
      if (s["status"] == "ok") continue;
      const std::string error = s["error"];
      const bool own_failure = error.find("/" + std::string(run) + "/") != std::string::npos;
      const bool did_not_start = error.rfind("the comparison did not start: ", 0) == 0;
      EXPECT_TRUE(own_failure || did_not_start || top["started"] == true) << error;
      if (top["started"] == false && !own_failure) {
        EXPECT_TRUE(did_not_start) << error;
        EXPECT_EQ(fs::exists(out / run / "map.png"), false);  // no result of a run never started
      }
    }
  }
}

// Case 7: compare under a 400 MB address-space limit: threads that cannot start are not a crash.
TEST(Limits, CompareUnderAnAddressSpaceLimitEndsCleanly) {
  const auto out = freshDir("address_space");
  const auto r = runBinary({"compare", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet",
                            "--cap", "10", "--set", "MappingApplication.max_steps=60"},
                           out.string() + ".err", [] {
                             // 430 MiB: room to start (the executable maps Python's embedding
                             // library), too little for every run of the comparison.
                             const rlimit l{rlim_t{430} << 20, rlim_t{430} << 20};
                             ::setrlimit(RLIMIT_AS, &l);
                           });
  ASSERT_GE(r.code, 0) << "killed by signal " << -r.code << ": " << r.err;
  EXPECT_TRUE(r.code == 0 || r.code == 1) << r.code << ": " << r.err;
  EXPECT_EQ(r.err.find("terminate called"), std::string::npos) << r.err;
  for (std::size_t at = 0, end; (end = r.err.find('\n', at)) != std::string::npos; at = end + 1)
    EXPECT_EQ(r.err.compare(at, 13, "budget-slam: "), 0) << r.err;
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_EQ(readJson(out / "summary.json")["status"], r.code == 0 ? "ok" : "failed");
}

// Case 7: `budget-slam run ... | head -c0`: the pipe is closed; no SIGPIPE death.
TEST(Limits, AClosedStdoutIsOneLineNotASignal) {
  const auto out = freshDir("closed_stdout");
  int p[2];
  ASSERT_EQ(::pipe(p), 0);
  ::close(p[0]);  // nobody reads
  std::vector<std::string> args = kRun;
  args.erase(std::find(args.begin(), args.end(), "--quiet"));
  const auto r = runBinary(with(args, out), out.string() + ".err", {}, p[1]);
  ::close(p[1]);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(isErrorLine(
      r.err, "cannot write to stdout (Broken pipe); the outputs are in " + out.string() + "/"));
  EXPECT_EQ(readJson(out / "summary.json")["status"], "ok");  // the run itself is whole
}

// Case 7: Ctrl-C, then SIGTERM 50 ms later (an impatient user, a scheduler's grace period): one
// line, exit 130, the outputs of the steps done.
TEST(Limits, ASecondSignalEndsTheRunLikeTheFirst) {
  for (const int delay_ms : {0, 400}) {
    SCOPED_TRACE(delay_ms);
    const auto out = freshDir("two_signals_" + std::to_string(delay_ms));
    const pid_t pid =
        startChild(kBin,
                   {"run", "-c", kMrptIni, "-i", kRoot + "/rawlogs/victoria_park.rawlog", "-o",
                    out.string(), "--quiet", "--backend", "graph"},
                   out.string() + ".err");
    ASSERT_GT(pid, 0);
    // Once it runs (its steps.csv exists), and then some.
    for (int k = 0; k < 3000 && !fs::exists(out / "steps.csv"); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    ::kill(pid, SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ::kill(pid, SIGTERM);
    const auto r = waitChild(pid);
    // The sidecar's notes on the values it sets over the -c file's come first; then one line.
    std::string err = slurp(out.string() + ".err");
    while (err.rfind("budget-slam: warning: ", 0) == 0) err.erase(0, err.find('\n') + 1);
    ASSERT_FALSE(r.signaled()) << "killed by signal " << -r.code << ": " << err;
    EXPECT_EQ(r.code, 130);
    EXPECT_EQ(lines(err), 1) << err;
    EXPECT_EQ(err.rfind("budget-slam: interrupted by Ctrl-C ", 0), 0u) << err;
    const auto s = readJson(out / "summary.json");
    EXPECT_EQ(s["status"], "interrupted");
  }
}

// Case 7: the signals come while the program starts, before any step: here while it waits for
// its -c file (a FIFO nobody writes yet). The handlers are there from the first line of main():
// the run ends as interrupted before its first step, one line, exit 130, never killed.
TEST(Limits, SignalsDuringStartUpEndTheRunCleanly) {
  const auto dir = freshDir("signals_at_start");
  fs::create_directories(dir);
  const auto fifo = dir / "config.ini";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const auto out = dir / "out";
  const pid_t pid =
      startChild(kBin, {"run", "-c", fifo.string(), "-i", kDemo, "-o", out.string(), "--quiet"},
                 (dir / "err").string());
  ASSERT_GT(pid, 0);
  EXPECT_TRUE(waitUntilBlockedOnFifo(pid));  // blocked opening its -c file
  ::kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ::kill(pid, SIGTERM);
  const auto r = feedFifoAndWait(pid, fifo.string(), slurp(kMrptIni));  // now the configuration
  const std::string err = slurp(dir / "err");
  ASSERT_FALSE(r.signaled()) << "killed by signal " << -r.code << ": " << err;
  EXPECT_EQ(r.code, 130);
  EXPECT_TRUE(isOneLine(err, Said::Interrupted, "interrupted by Ctrl-C before the first step"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["started"], false);
}
