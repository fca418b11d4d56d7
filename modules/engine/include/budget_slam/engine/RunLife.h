#pragma once
// One command's life (docs/ARCHITECTURE.md "A run"): its output folder and the lock on it, what
// it was given, and how it ends. run, compare and localize each hold one; a failure anywhere ends
// the command through end(), which writes summary.json (last, through the command's engine once
// there is one) and makes the one error line.
#include <functional>
#include <optional>
#include <string>

#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/report/OutputFolder.h"

namespace budget_slam::runs {

class RunLife {
 public:
  /// How the command's engine ends the command once it exists (RunDriver::finish,
  /// Localizer::finish, ...): given `outcome` with status, kind, error and given set (given's
  /// "started" false), it writes summary.json and may replace `outcome` with what it wrote.
  /// Returns why summary.json could not be written ("" when it was); may throw.
  using Finisher = std::function<std::string(RunOutcome& outcome)>;

  /// `given`: what the command was given, into summary.json (rawlog, config, ...).
  explicit RunLife(RunGiven given = {});

  /// Creates and locks the output folder (report::OutputFolder; an earlier run moved aside with
  /// `force`, recorded as given's earlier_run_moved_to). Throws Error as OutputFolder does.
  report::OutputFolder& open(const std::string& outdir, bool force);
  /// open() for a command that failed before it could open its folder: summary.json is then
  /// written there when the folder can be made. Never throws; false when there is no folder.
  bool openToSayWhy(const std::string& outdir, bool force);
  report::OutputFolder& folder() { return *folder_; }
  /// The folder's path, "" when none was made.
  std::string path() const { return folder_ ? folder_->path() : std::string(); }
  /// "<folder> held an earlier run; its files were moved to <earlier>/", "" when it held none.
  std::string earlierRunNote() const;

  /// What the command was given (summary.json's "given" block; the caller adds to it).
  RunGiven& given() { return given_; }
  /// Once the engine exists, it ends the command (see Finisher); before, end() writes the
  /// summary itself.
  void setFinisher(Finisher finisher) { finisher_ = std::move(finisher); }

  /// How the command ended: the outcome summary.json was written from and the one line.
  struct End {
    RunOutcome outcome;
    std::string line;  ///< the error, and why summary.json could not be written when it could not
  };
  /// Ends the command as `status` for `why` (made one printable line): summary.json through the
  /// finisher, or with the given block alone when there is none (and a folder). The outcome keeps
  /// the status, kind and error asked for, whatever the finisher made of them. Never throws.
  End end(const std::string& why, RunStatus status, ErrorKind kind);
  /// end() for `e` as failed: its failureLine (core/Text.h) and its error kind.
  End endOn(const std::exception& e);
  /// end() for a stop request: "interrupted by <signal><where>".
  End endInterrupted(const std::string& where);
  /// "interrupted by <signal><where>" (core/Cancellation.h's signal name).
  static std::string interruptedLine(const std::string& where);

  /// Writes summary.json into the folder for `outcome` with the given block (when there is a
  /// folder). Returns why it could not be written, "" when it was or when there is no folder.
  std::string writeSummaryHere(RunOutcome outcome) const;

 private:
  RunGiven given_;
  std::optional<report::OutputFolder> folder_;
  Finisher finisher_;
};

}  // namespace budget_slam::runs
