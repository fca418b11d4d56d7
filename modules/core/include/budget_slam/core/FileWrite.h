#pragma once
#include <sys/types.h>

#include <cstddef>
#include <string>
#include <string_view>

namespace budget_slam {

/// Writes `bytes` to `path` so that a reader sees the previous file or the new one, never a part:
/// the bytes go to `<path>.tmp` (reusing the disk space reserveFileSpace() set aside there, if
/// any), which is flushed to disk (fsync) and renamed over `path`. Every system call is checked:
/// on a failure (disk full, read-only folder, file-size limit) the temporary file is removed,
/// `path` is left as it was, and Error "cannot write '<path>' (<reason>)" is thrown.
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// Sets `bytes` of disk space aside in `<path>.tmp` for a later writeFileAtomically(path), so
/// that a run that filled the disk can still write a small file there (summary.json says why
/// the run failed). Best effort: returns false when the space cannot be had.
bool reserveFileSpace(const std::string& path, std::size_t bytes);

/// A file written one whole line at a time and flushed after each (steps.csv, evictions.csv:
/// readable while the run goes, and after it stops early). Each line goes out with write(2); when
/// the disk takes only part of it, the file is cut back to the end of the previous line
/// (ftruncate), so that it never ends inside a line. After a failure every later append() throws
/// the same error: the file never skips a line.
class LineFile {
 public:
  /// Creates or truncates `path`. Throws Error "cannot write '<path>' (<reason>)".
  explicit LineFile(std::string path);
  ~LineFile();
  LineFile(const LineFile&) = delete;
  LineFile& operator=(const LineFile&) = delete;

  /// `line` must end with '\n'. Throws Error naming the file.
  void append(std::string_view line);
  /// Flushes the file to disk (fsync). Throws Error naming the file, also for an earlier failure.
  void sync();
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(int err);
  std::string path_;
  int fd_ = -1;
  off_t size_ = 0;     ///< bytes of complete lines on disk
  std::string error_;  ///< first failure, "" while none
};

/// "cannot write '<path>' (<strerror(err)>)".
std::string cannotWrite(const std::string& path, int err);

}  // namespace budget_slam
