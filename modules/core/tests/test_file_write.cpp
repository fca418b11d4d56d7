// Checked, atomic output files: a reader never sees a torn file, and a write that fails (a full
// disk, a file-size limit) is an error naming the file. The failures are made real with a
// file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored): write(2) then fails with EFBIG exactly as it
// fails with ENOSPC on a full disk; and with DiskSpaceForTests, a full disk made in-process. The
// full-disk case itself runs on a tmpfs in tests/.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <vector>

#include "TempFiles.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"

using namespace budget_slam;
using namespace budget_slam::test;
namespace fs = std::filesystem;

namespace {

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

}  // namespace

TEST(FileWrite, AtomicWriteReplacesAndLeavesNoTemporaryFile) {
  const auto d = tempDir("file_write_atomic");
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
  const auto d = tempDir("file_write_atomic_fail");
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
  const auto d = tempDir("file_write_reserve");
  const std::string p = (d / "summary.json").string();
  ASSERT_TRUE(reserveFileSpace(p, 32768));
  EXPECT_EQ(fs::file_size(p + ".tmp"), 32768u);
  writeFileAtomically(p, "{}\n");
  EXPECT_EQ(slurp(p), "{}\n");  // cut to its own size
  EXPECT_FALSE(fs::exists(p + ".tmp"));
}

TEST(FileWrite, LineFileNeverEndsInsideALine) {
  const auto d = tempDir("file_write_lines");
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

TEST(FileWrite, ASimulatedFullDiskFailsLikeARealOne) {
  const auto d = tempDir("file_write_disk_space");
  const std::string p = (d / "steps.csv").string();
  std::string error;
  {
    DiskSpaceForTests disk(45);
    LineFile f(p);
    f.append(std::string(29, 'a') + "\n");
    error = errorOf([&] { f.append(std::string(29, 'b') + "\n"); });  // 15 of 30 bytes fit
  }
  EXPECT_EQ(error, "cannot write '" + p + "' (No space left on device)");
  EXPECT_EQ(slurp(p), std::string(29, 'a') + "\n");
  writeFileAtomically(p, "room again\n");  // the limit is gone with its object
  EXPECT_EQ(slurp(p), "room again\n");
}

TEST(FileWrite, CommitNewNeverReplacesAFile) {
  const auto d = tempDir("file_write_commit_new");
  const std::string p = (d / "out.rawlog").string();
  {
    PendingFile f(p);
    f.write("mine\n");
    f.commitNew();
  }
  EXPECT_EQ(slurp(p), "mine\n");
  std::ofstream(d / "theirs.ini") << "theirs\n";
  const std::string q = (d / "theirs.ini").string();
  std::string error;
  {
    PendingFile f(q);
    f.write("mine\n");
    error = errorOf([&] { f.commitNew(); });
  }
  EXPECT_EQ(error, "cannot write '" + q + "' (File exists)");
  EXPECT_EQ(slurp(q), "theirs\n");
  EXPECT_FALSE(fs::exists(q + ".tmp"));
}

TEST(FileWrite, APendingFileNotCommittedLeavesNothing) {
  const auto d = tempDir("file_write_not_committed");
  const std::string p = (d / "a.txt").string();
  std::ofstream(p) << "before\n";
  {
    PendingFile f(p);
    f.write("half");
  }
  EXPECT_EQ(slurp(p), "before\n");
  EXPECT_FALSE(fs::exists(p + ".tmp"));
}

// The reservation keeps its descriptor: the file is written even when the process has no
// descriptor left to open one (a run under `ulimit -n`).
TEST(FileWrite, ReservedFileIsWrittenWithoutANewDescriptor) {
  const auto d = tempDir("file_write_reserve_fd");
  const std::string p = (d / "summary.json").string();
  ASSERT_TRUE(reserveFileSpace(p, 4096));
  std::vector<int> taken;
  for (int fd; (fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC)) >= 0;) taken.push_back(fd);
  ASSERT_EQ(errno, EMFILE);
  const std::string other = (d / "other.txt").string();
  const std::string refused = errorOf([&] { writeFileAtomically(other, "x"); });
  const std::string written = errorOf([&] { writeFileAtomically(p, "{}\n"); });
  for (int fd : taken) ::close(fd);
  EXPECT_EQ(refused, "cannot write '" + other + "' (Too many open files)");
  EXPECT_EQ(written, "no error");
  EXPECT_EQ(slurp(p), "{}\n");
}

TEST(FileWrite, AnUnusedReservationIsGivenBack) {
  const auto d = tempDir("file_write_release");
  const std::string p = (d / "summary.json").string();
  ASSERT_TRUE(reserveFileSpace(p, 4096));
  EXPECT_TRUE(fs::exists(p + ".tmp"));
  releaseFileSpace(p);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  releaseFileSpace(p);  // twice: nothing to do
}
