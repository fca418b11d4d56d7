#pragma once
#include <string>

namespace budget_slam::report {

/// An advisory lock on an output folder while a process writes it (docs/RELIABILITY.md "Two
/// runs into one folder"): flock(2) on `<folder>/.budget-slam.lock`, which holds the holder's
/// process id. A second budget-slam (or a sweep, which takes the same lock) is refused at once
/// with one line naming that process; the kernel drops the lock when its holder ends, however it
/// ends, so a crashed run never leaves a folder locked. The file is removed when the lock is let
/// go.
class FolderLock {
 public:
  /// Takes the lock on `folder` (which must exist). Throws Error
  ///   "output folder 'OUT' is in use by process 1234 (it holds OUT/.budget-slam.lock); wait for
  ///   it to end or give another output folder".
  explicit FolderLock(std::string folder);
  ~FolderLock();
  /// Writes this process's id into the lock file, for the message of whoever is refused. Apart
  /// from the lock, so that a folder's owner can first set its disk space aside (on a disk of one
  /// free page the id would take it); until then a refused process names "another process".
  void announce();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  /// The lock file's name inside a folder (never an output, never moved aside).
  static constexpr const char* kFileName = ".budget-slam.lock";

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace budget_slam::report
