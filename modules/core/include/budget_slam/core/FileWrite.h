#pragma once
// Checked output files (docs/RELIABILITY.md "Outputs on a full disk"): a reader never sees a torn
// file, a failed write is an Error naming the file, and no file is replaced by accident.
#include <sys/types.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace budget_slam {

/// A file written under the temporary name `<path>.tmp` and put in place whole by commit() or
/// commitNew(); destroyed without either, it removes its temporary file and `path` is left as it
/// was. Every system call is checked: a failure (disk full, read-only folder, file-size limit,
/// no file descriptor left) throws Error "cannot write '<path>' (<reason>)" and removes the
/// temporary file. Space set aside by reserveFileSpace(path) is reused (no new descriptor, no new
/// disk block for its first bytes).
class PendingFile {
 public:
  explicit PendingFile(std::string path);
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  /// Appends `bytes`.
  void write(std::string_view bytes);
  /// Flushes to disk (fsync) and renames over `path`, replacing what is there.
  void commit();
  /// Flushes to disk and puts the file at `path` only if nothing is there (link(2), which never
  /// replaces): the file-system check and the write are one step, so a file made by someone else
  /// meanwhile is never replaced. Throws Error "'<path>' exists (...)" when something is there.
  void commitNew();
  const std::string& path() const { return path_; }
  std::size_t size() const { return size_; }

 private:
  void flushAndClose();
  [[noreturn]] void fail(int err);
  std::string path_, tmp_;
  int fd_ = -1;
  std::size_t size_ = 0;
  std::size_t reserved_ = 0;  ///< bytes of disk the file had from reserveFileSpace()
  bool done_ = false;
};

/// Writes `bytes` to `path` through a PendingFile and commit(): a reader sees the previous file or
/// the new one, never a part. Throws Error "cannot write '<path>' (<reason>)".
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// Sets `bytes` of disk space aside in `<path>.tmp`, and keeps a file descriptor open on it, for a
/// later PendingFile(path): a run that filled the disk, or used up its file descriptors, can still
/// write a small file there (summary.json says why the run failed). Best effort: false when the
/// space cannot be had. At most one reservation a path; a new one replaces the old.
bool reserveFileSpace(const std::string& path, std::size_t bytes);
/// Gives a reservation of `path` back, when unused: its descriptor is closed and its temporary
/// file removed (a folder then holds no stray `<name>.tmp`).
void releaseFileSpace(const std::string& path);

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

/// A disk that is full after `bytes` more bytes, for tests: while one lives, every write of this
/// module (PendingFile, LineFile, reserveFileSpace) takes what is left of `bytes` and then fails
/// with ENOSPC, as write(2) does on a full disk. Process-wide; one at a time.
class DiskSpaceForTests {
 public:
  explicit DiskSpaceForTests(std::size_t bytes);
  ~DiskSpaceForTests();
  DiskSpaceForTests(const DiskSpaceForTests&) = delete;
  DiskSpaceForTests& operator=(const DiskSpaceForTests&) = delete;
};

}  // namespace budget_slam
