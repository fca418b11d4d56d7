#pragma once
#include <memory>
#include <string>
#include <vector>

namespace budget_slam::report {

class FolderLock;

/// The folder a run writes into (docs/OUTPUTS.md, docs/RELIABILITY.md). While any copy of it
/// lives, the folder is locked (FolderLock): a second run into it is refused with one line naming
/// the process that holds it. It refuses a non-empty folder unless `force` is set, and even then
/// never deletes anything of anyone else's: what an earlier budget-slam run left there (the output
/// files of `run`, `compare` and `localize`, their temporary files, `states/`, compare's run
/// folders) is first moved into a subfolder `earlier_run_<date>-<time>/` named for that run (the
/// time its summary.json, else its newest file, was written); other files are left where they
/// are. The one exception is a run that ended before its first step (its summary.json says
/// `"started": false`): it made nothing worth keeping, and its files are replaced without --force,
/// so that the corrected command simply runs.
class OutputFolder {
 public:
  /// Creates the folder (and parents), locks it, moves an earlier run aside (`force`), and sets
  /// disk space aside for summary.json (so that a run that fills the disk, or runs out of file
  /// descriptors, can still say why it failed). Throws Error
  ///   "output folder 'OUT' is in use by process 1234 (...)",
  /// ConfigError "output folder 'OUT' is not empty (use --force to write into it)".
  OutputFolder(std::string path, bool force);

  const std::string& path() const { return path_; }
  /// Path of `name` inside the folder (subfolders are created on demand).
  std::string file(const std::string& name) const;
  /// The subfolder (a name inside path()) the earlier run's files were moved to; "" if none.
  const std::string& earlierRun() const { return earlier_run_; }

  /// The names of the files and folders `run`, `compare` and `localize` write at the top of a
  /// folder.
  static const std::vector<std::string>& outputNames();
  /// Space set aside for summary.json [bytes]: twice the largest summary a run writes. Where it
  /// cannot be had, one 4 KiB page, which the short summary (writeSummaryJson) fits.
  static constexpr std::size_t kSummaryReserve = 8192;

 private:
  /// The lock and the reservation, shared by every copy of the folder; given back with the last.
  struct Hold;
  void moveEarlierRun();
  std::string path_;
  std::string earlier_run_;
  std::shared_ptr<Hold> hold_;
};

}  // namespace budget_slam::report
