#include "budget_slam/core/FileWrite.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "budget_slam/core/Error.h"

namespace budget_slam {
namespace {

/// Writes all of `bytes` at the current offset; false with errno set on failure (a short write
/// on a full disk is retried once more, which then fails with ENOSPC).
bool writeAll(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
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

}  // namespace

std::string cannotWrite(const std::string& path, int err) {
  return "cannot write '" + path + "' (" + std::strerror(err) + ")";
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".tmp";
  // No O_TRUNC: blocks reserved in the temporary file are overwritten, not given back first.
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(cannotWrite(path, errno));
  const auto fail = [&](int err) {
    ::close(fd);
    ::unlink(tmp.c_str());  // our own temporary file
    throw Error(cannotWrite(path, err));
  };
  if (!writeAll(fd, bytes)) fail(errno);
  if (::ftruncate(fd, static_cast<off_t>(bytes.size())) != 0) fail(errno);
  if (::fsync(fd) != 0) fail(errno);
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw Error(cannotWrite(path, err));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw Error(cannotWrite(path, err));
  }
  syncFolder(path);
}

bool reserveFileSpace(const std::string& path, std::size_t bytes) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  // Real blocks (not a sparse file), so that overwriting them later needs no new space.
  const std::vector<char> zeros(bytes, ' ');
  const bool ok = writeAll(fd, std::string_view(zeros.data(), zeros.size())) && ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) ::unlink(tmp.c_str());
  return ok;
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

}  // namespace budget_slam
