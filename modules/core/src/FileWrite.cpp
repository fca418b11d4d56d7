#include "budget_slam/core/FileWrite.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

#include "budget_slam/core/Error.h"

namespace budget_slam {
namespace {

/// Bytes DiskSpaceForTests still lets through; negative: no limit.
std::mutex g_space_mutex;
long long g_space_left = -1;

/// Of `want` bytes, how many the simulated disk takes (all without a DiskSpaceForTests).
std::size_t spaceFor(std::size_t want) {
  std::lock_guard<std::mutex> lock(g_space_mutex);
  if (g_space_left < 0) return want;
  const std::size_t got = std::min<std::size_t>(want, static_cast<std::size_t>(g_space_left));
  g_space_left -= static_cast<long long>(got);
  return got;
}

/// Writes all of `bytes` at the current offset; false with errno set on failure (a short write
/// on a full disk is retried once more, which then fails with ENOSPC). The first `reserved` bytes
/// go to blocks the file already has (a reservation): they take no new space.
bool writeAll(int fd, std::string_view bytes, std::size_t reserved = 0) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t free = done < reserved ? reserved - done : 0;
    const std::size_t want = bytes.size() - done;
    const std::size_t allowed = std::min(want, free) + spaceFor(want - std::min(want, free));
    if (allowed == 0) {
      errno = ENOSPC;
      return false;
    }
    const ssize_t n = ::write(fd, bytes.data() + done, allowed);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = ENOSPC;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

/// Makes a rename in `dir` durable. Failure only weakens durability after a power loss.
void syncFolder(const std::string& file) {
  const auto dir = std::filesystem::path(file).parent_path();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

/// Open descriptors on reserved temporary files (reserveFileSpace), by the temporary file's path.
std::mutex g_reserved_mutex;
std::map<std::string, int>& reserved() {
  static std::map<std::string, int> fds;
  return fds;
}

/// The descriptor reserved for `tmp`, taken out of the table, or -1.
int takeReserved(const std::string& tmp) {
  std::lock_guard<std::mutex> lock(g_reserved_mutex);
  const auto it = reserved().find(tmp);
  if (it == reserved().end()) return -1;
  const int fd = it->second;
  reserved().erase(it);
  return fd;
}

}  // namespace

std::string cannotWrite(const std::string& path, int err) {
  return "cannot write '" + path + "' (" + std::strerror(err) + ")";
}

PendingFile::PendingFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  fd_ = takeReserved(tmp_);
  if (fd_ >= 0 && ::lseek(fd_, 0, SEEK_SET) == 0) {  // the space set aside, from its start
    struct stat st {};
    if (::fstat(fd_, &st) == 0) reserved_ = static_cast<std::size_t>(st.st_size);
    return;
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(cannotWrite(path_, errno));
}

PendingFile::~PendingFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!done_) ::unlink(tmp_.c_str());  // our own temporary file
}

void PendingFile::fail(int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(tmp_.c_str());
  done_ = true;
  throw Error(cannotWrite(path_, err));
}

void PendingFile::write(std::string_view bytes) {
  if (fd_ < 0) throw Error(cannotWrite(path_, EBADF));
  if (!writeAll(fd_, bytes, reserved_ > size_ ? reserved_ - size_ : 0)) fail(errno);
  size_ += bytes.size();
}

void PendingFile::flushAndClose() {
  if (fd_ < 0) throw Error(cannotWrite(path_, EBADF));
  // A reused reservation is longer than the file: cut it to the bytes written.
  if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0) fail(errno);
  if (::fsync(fd_) != 0) fail(errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(errno);
}

void PendingFile::commit() {
  flushAndClose();
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) fail(errno);
  done_ = true;
  syncFolder(path_);
}

void PendingFile::commitNew() {
  flushAndClose();
  if (::link(tmp_.c_str(), path_.c_str()) != 0) {
    int err = errno;
    // File systems without hard links: a rename that refuses to replace.
    if (err == EPERM || err == ENOTSUP || err == ENOSYS) {
      if (::renameat2(AT_FDCWD, tmp_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE) == 0) {
        done_ = true;
        syncFolder(path_);
        return;
      }
      err = errno;
    }
    fail(err);
  }
  ::unlink(tmp_.c_str());
  done_ = true;
  syncFolder(path_);
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  PendingFile f(path);
  f.write(bytes);
  f.commit();
}

bool reserveFileSpace(const std::string& path, std::size_t bytes) {
  const std::string tmp = path + ".tmp";
  releaseFileSpace(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  // Real blocks (not a sparse file), so that overwriting them later needs no new space.
  const std::vector<char> blanks(bytes, ' ');
  if (!writeAll(fd, std::string_view(blanks.data(), blanks.size())) || ::fsync(fd) != 0) {
    ::close(fd);
    ::unlink(tmp.c_str());
    return false;
  }
  std::lock_guard<std::mutex> lock(g_reserved_mutex);
  reserved()[tmp] = fd;
  return true;
}

void releaseFileSpace(const std::string& path) {
  const std::string tmp = path + ".tmp";
  const int fd = takeReserved(tmp);
  if (fd < 0) return;
  ::close(fd);
  ::unlink(tmp.c_str());
}

LineFile::LineFile(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(cannotWrite(path_, errno));
}

LineFile::~LineFile() {
  if (fd_ >= 0) ::close(fd_);
}

void LineFile::fail(int err) {
  // Cut a partly written line off again: the file ends at the end of its last whole line.
  if (::ftruncate(fd_, size_) == 0) ::lseek(fd_, size_, SEEK_SET);
  error_ = cannotWrite(path_, err);
  throw Error(error_);
}

void LineFile::append(std::string_view line) {
  if (!error_.empty()) throw Error(error_);
  if (!writeAll(fd_, line)) fail(errno);
  size_ += static_cast<off_t>(line.size());
}

void LineFile::sync() {
  if (!error_.empty()) throw Error(error_);
  if (::fsync(fd_) != 0) fail(errno);
}

DiskSpaceForTests::DiskSpaceForTests(std::size_t bytes) {
  std::lock_guard<std::mutex> lock(g_space_mutex);
  g_space_left = static_cast<long long>(bytes);
}

DiskSpaceForTests::~DiskSpaceForTests() {
  std::lock_guard<std::mutex> lock(g_space_mutex);
  g_space_left = -1;
}

}  // namespace budget_slam
