#pragma once
#include <string>
#include <vector>

namespace budget_slam::report {

/// The folder a run writes into (docs/OUTPUTS.md). It refuses a non-empty folder unless
/// `force` is set, and even then never deletes anything: it only (over)writes its own files.
class OutputFolder {
 public:
  /// Creates the folder (and parents). Throws ConfigError
  ///   "output folder 'OUT' is not empty (use --force to write into it)".
  OutputFolder(std::string path, bool force);

  const std::string& path() const { return path_; }
  /// Path of `name` inside the folder (subfolders are created on demand).
  std::string file(const std::string& name) const;

 private:
  std::string path_;
};

}  // namespace budget_slam::report
