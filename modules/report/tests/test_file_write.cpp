// Checked, atomic output files: a reader never sees a torn file, and a write that fails (a full
// disk, a file-size limit) is an error naming the file. The failures are made real with a
// file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored): write(2) then fails with EFBIG exactly as it
// fails with ENOSPC on a full disk. The full-disk case itself runs on a tmpfs in tests/.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/FileWrite.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/RunFiles.h"

using namespace budget_slam;
using namespace budget_slam::report;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("budget_slam_file_write_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Files of this process may not grow past `bytes` while it lives (restored after).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit l = saved_;
    l.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &l);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_);
  }

 private:
  rlimit saved_{};
  void (*previous_)(int) = SIG_DFL;
};

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(FileWrite, AtomicWriteReplacesAndLeavesNoTemporaryFile) {
  const auto d = tempDir("atomic");
  const std::string p = (d / "a.txt").string();
  writeFileAtomically(p, "first\n");
  writeFileAtomically(p, "second\n");
  EXPECT_EQ(slurp(p), "second\n");
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  const std::string missing = (d / "no_such" / "a.txt").string();
  EXPECT_EQ(errorOf([&] { writeFileAtomically(missing, "x"); }),
            "cannot write '" + missing + "' (No such file or directory)");
}

TEST(FileWrite, AFailedAtomicWriteKeepsThePreviousFile) {
  const auto d = tempDir("atomic_fail");
  const std::string p = (d / "summary.json").string();
  writeFileAtomically(p, "{\"status\": \"ok\"}\n");
  std::string error;
  {
    FileSizeLimit limit(1000);
    error = errorOf([&] { writeFileAtomically(p, std::string(5000, 'x')); });
  }
  EXPECT_EQ(error, "cannot write '" + p + "' (File too large)");
  EXPECT_EQ(slurp(p), "{\"status\": \"ok\"}\n");  // the old file, whole
  EXPECT_FALSE(fs::exists(p + ".tmp"));
}

TEST(FileWrite, ReservedSpaceIsReusedForTheFile) {
  const auto d = tempDir("reserve");
  const std::string p = (d / "summary.json").string();
  ASSERT_TRUE(reserveFileSpace(p, 32768));
  EXPECT_EQ(fs::file_size(p + ".tmp"), 32768u);
  writeFileAtomically(p, "{}\n");
  EXPECT_EQ(slurp(p), "{}\n");  // cut to its own size
  EXPECT_FALSE(fs::exists(p + ".tmp"));
}

TEST(FileWrite, LineFileNeverEndsInsideALine) {
  const auto d = tempDir("lines");
  const std::string p = (d / "steps.csv").string();
  const std::string line = std::string(29, 'a') + "\n";  // 30 bytes
  std::string first, second;
  {
    LineFile f(p);
    FileSizeLimit limit(100);  // room for 3 lines and a third of the 4th
    for (int i = 0; i < 3; ++i) f.append(line);
    first = errorOf([&] { f.append(line); });
    second = errorOf([&] { f.append("b\n"); });  // never a line skipped
  }
  EXPECT_EQ(first, "cannot write '" + p + "' (File too large)");
  EXPECT_EQ(second, first);
  EXPECT_EQ(slurp(p), line + line + line);  // the partial 4th line was cut off again
}

TEST(CsvWriter, AFailedRowIsNotHalfWritten) {
  const auto d = tempDir("csv_fail");
  const std::string p = (d / "steps.csv").string();
  CsvWriter csv(p, {"a", "b"});
  std::string error;
  {
    FileSizeLimit limit(20);
    csv.cell(1.5).cell(std::string("xy")).endRow();                                 // 4 + 7 bytes
    error = errorOf([&] { csv.cell(123456.25).cell(std::string("z")).endRow(); });  // 12 more
  }
  EXPECT_EQ(error, "cannot write '" + p + "' (File too large)");
  EXPECT_EQ(slurp(p), "a,b\n1.5,xy\n");
}

TEST(RunFiles, SummaryIsValidUtf8WhateverTheErrorTextHolds) {
  const auto d = tempDir("utf8");
  const std::string p = (d / "summary.json").string();
  // A corrupt class name echoed by an error message: bytes that are not UTF-8.
  writeJson(p, {{"status", "failed"},
                {"error", std::string("class 'CObs\xff\xfe"
                                      "x' unknown")}});
  const auto j = nlohmann::json::parse(slurp(p));
  EXPECT_EQ(j["status"], "failed");
  EXPECT_EQ(j["error"], "class 'CObs\xEF\xBF\xBD\xEF\xBF\xBDx' unknown");  // U+FFFD each
}

TEST(OutputFolder, AForcedRunMovesTheEarlierRunAside) {
  const auto d = tempDir("forced");
  std::ofstream(d / "summary.json") << "{}\n";
  std::ofstream(d / "ground_truth.tum") << "0 0 0 0 0 0 0 1\n";
  std::ofstream(d / "steps.csv.tmp") << "cut";
  fs::create_directories(d / "states");
  std::ofstream(d / "states" / "step_3.txt") << "x";
  std::ofstream(d / "notes.txt") << "mine";

  OutputFolder f(d.string(), true);
  const std::string earlier = f.earlierRun();
  ASSERT_EQ(earlier.rfind("earlier_run_", 0), 0u) << earlier;
  const fs::path moved = d / earlier;
  for (const char* name : {"summary.json", "ground_truth.tum", "steps.csv.tmp", "states"}) {
    EXPECT_TRUE(fs::exists(moved / name)) << name;
    EXPECT_FALSE(fs::exists(d / name)) << name;
  }
  EXPECT_TRUE(fs::exists(moved / "states" / "step_3.txt"));
  EXPECT_EQ(slurp(d / "notes.txt"), "mine");  // not ours: left where it is
  // The folder now holds the user's file, the earlier run and the space set aside for the summary.
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"notes.txt", earlier, "summary.json.tmp"}));

  // A second forced run keeps both earlier runs apart.
  std::ofstream(d / "summary.json") << "{}\n";
  OutputFolder g(d.string(), true);
  EXPECT_NE(g.earlierRun(), earlier);
  EXPECT_TRUE(fs::exists(d / g.earlierRun() / "summary.json"));
  EXPECT_TRUE(fs::exists(d / earlier / "summary.json"));
}
