#include "budget_slam/report/FolderLock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::report {
namespace {

/// Who holds the lock, as its file says: "process 1234". The holder writes its id right after it
/// takes the lock, so an empty file is read again for a moment before giving up on the id.
std::string holderOf(int fd) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    const std::string text = n > 0 ? trimmed(std::string(buf, static_cast<std::size_t>(n))) : "";
    if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos)
      return "process " + text;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return "another process";
}

bool sameFile(int fd, const std::string& path) {
  struct stat a {
  }, b{};
  return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev &&
         a.st_ino == b.st_ino;
}

}  // namespace

FolderLock::FolderLock(std::string folder)
    : path_((std::filesystem::path(folder) / kFileName).string()) {
  const auto failed = [&](int err) {
    return Error("output folder '" + folder + "': cannot lock it (" + path_ + ": " +
                 std::strerror(err) + ")");
  };
  // The previous holder removes the file as it lets go: a lock taken on a file no longer in the
  // folder does not count, and is taken again on the new one.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw failed(errno);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err == EWOULDBLOCK) {
        const std::string holder = holderOf(fd);
        ::close(fd);
        throw Error("output folder '" + folder + "' is in use by " + holder + " (it holds " +
                    path_ + "); wait for it to end or give another output folder");
      }
      ::close(fd);
      // A file system without locks (some network mounts): written without one.
      if (err == ENOLCK || err == EOPNOTSUPP || err == ENOSYS) return;
      throw failed(err);
    }
    if (!sameFile(fd, path_)) {
      ::close(fd);
      continue;
    }
    fd_ = fd;
    return;
  }
  throw failed(EAGAIN);
}

void FolderLock::announce() {
  if (fd_ < 0) return;
  // Best effort: on a full disk the lock holds without the id ("another process").
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
    static_cast<void>(written);
  }
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still held: the next holder locks a fresh file
  ::close(fd_);
}

}  // namespace budget_slam::report
