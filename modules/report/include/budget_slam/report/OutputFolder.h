#pragma once
#include <string>
#include <vector>

namespace budget_slam::report {

/// The folder a run writes into (docs/OUTPUTS.md). It refuses a non-empty folder unless `force`
/// is set, and even then never deletes anything. A forced run never mixes its files with an
/// earlier run's: what an earlier budget-slam run left there (the output files of `run` and
/// `compare`, their temporary files, `states/`, compare's run folders) is first moved into a
/// subfolder `earlier_run_<date>-<time>/` named for that run (the time its summary.json, else its
/// newest file, was written); other files are left where they are.
class OutputFolder {
 public:
  /// Creates the folder (and parents), moves an earlier run aside (`force`), and sets disk space
  /// aside for summary.json (so that a run that fills the disk can still say why it failed).
  /// Throws ConfigError
  ///   "output folder 'OUT' is not empty (use --force to write into it)".
  OutputFolder(std::string path, bool force);

  const std::string& path() const { return path_; }
  /// Path of `name` inside the folder (subfolders are created on demand).
  std::string file(const std::string& name) const;
  /// The subfolder (a name inside path()) the earlier run's files were moved to; "" if none.
  const std::string& earlierRun() const { return earlier_run_; }

  /// The names of the files and folders `run` and `compare` write at the top of a folder.
  static const std::vector<std::string>& outputNames();
  /// Space set aside for summary.json [bytes].
  static constexpr std::size_t kSummaryReserve = 32768;

 private:
  void moveEarlierRun();
  std::string path_;
  std::string earlier_run_;
};

}  // namespace budget_slam::report
