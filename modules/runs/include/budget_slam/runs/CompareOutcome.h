#pragma once
// How a compare ends, typed: its status, error kind and first error, and the lines it says.
#include <string>
#include <vector>

#include "budget_slam/engine/RunStatus.h"

namespace budget_slam::runs {

/// One line a comparison says on stderr once its runs are done, typed: what it is and its text
/// (printed as "budget-slam: [error: |warning: ]<text>").
struct CompareLine {
  enum class Kind { Error, Warning, Interrupted };
  Kind kind = Kind::Error;
  std::string text;
  /// The line without "budget-slam: ": "error: <text>", "warning: <text>" or "<text>".
  std::string shown() const {
    return (kind == Kind::Error ? "error: " : kind == Kind::Warning ? "warning: " : "") + text;
  }
  bool operator==(const CompareLine& o) const { return kind == o.kind && text == o.text; }
};

/// How compare ends: its status (and so its exit code), the first error (its summary.json), and
/// one stderr line a run or localization that did not end ok and a warning a failed shadow
/// reducer.
struct CompareOutcome {
  RunStatus status = RunStatus::Ok;
  ErrorKind kind = ErrorKind::None;
  std::string first_error;
  std::vector<CompareLine> lines;  ///< in the order they are said

  /// A run that ended `s` (failed or interrupted) for the reason `line`. An interrupted run
  /// makes the comparison interrupted unless another failed; with `keep_first`, a status already
  /// set stays.
  void add(RunStatus s, ErrorKind k, const std::string& line, bool keep_first) {
    if (!keep_first || status == RunStatus::Ok) {
      const bool interrupted =
          s == RunStatus::Interrupted && (keep_first || status != RunStatus::Failed);
      status = interrupted ? RunStatus::Interrupted : RunStatus::Failed;
      if (kind == ErrorKind::None || !interrupted) kind = interrupted ? ErrorKind::Stopped : k;
    }
    if (first_error.empty()) first_error = line;
    lines.push_back(
        {s == RunStatus::Interrupted ? CompareLine::Kind::Interrupted : CompareLine::Kind::Error,
         line});
  }
  int exitCode() const { return runs::exitCode(status, kind); }
};

}  // namespace budget_slam::runs
