#include "budget_slam/engine/RunLife.h"

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/SummaryJson.h"

namespace budget_slam::runs {

RunLife::RunLife(RunGiven given) : given_(std::move(given)) {}

report::OutputFolder& RunLife::open(const std::string& outdir, bool force) {
  folder_.emplace(outdir, force);
  if (!folder_->earlierRun().empty()) given_.earlier_run_moved_to = folder_->earlierRun();
  return *folder_;
}

bool RunLife::openToSayWhy(const std::string& outdir, bool force) {
  if (folder_) return true;
  if (outdir.empty()) return false;
  try {
    open(outdir, force);
  } catch (const Error&) {
    // The folder's own error is not this command's: its line says why it failed.
  }
  return folder_.has_value();
}

std::string RunLife::earlierRunNote() const {
  if (!folder_ || folder_->earlierRun().empty()) return "";
  return folder_->path() + " held an earlier run; its files were moved to " +
         folder_->earlierRun() + "/";
}

std::string RunLife::writeSummaryHere(RunOutcome outcome) const {
  if (!folder_) return "";
  try {
    writeSummary(folder_->file("summary.json"), outcome);
  } catch (const std::exception& e) {
    return failureLine(e);
  }
  return "";
}

RunLife::End RunLife::end(const std::string& why, RunStatus status, ErrorKind kind) {
  End end;
  // One printable line whatever the message echoes (corrupt bytes of a file, say).
  const std::string msg = printable(why);
  std::string not_saved;
  try {
    end.outcome.fail(status, kind, msg);
    end.outcome.given = given_;
    // A command that ended before its first step made nothing to keep: the next one into the
    // folder replaces its files (report/OutputFolder.h). The finisher says when it did.
    end.outcome.given.started = false;
    not_saved = finisher_ ? finisher_(end.outcome) : writeSummaryHere(end.outcome);
  } catch (const std::exception& e) {
    not_saved = failureLine(e);
  }
  end.outcome.status = status, end.outcome.kind = kind, end.outcome.error = msg;
  end.line = withAlso(msg, not_saved);
  return end;
}

RunLife::End RunLife::endOn(const std::exception& e) {
  return end(failureLine(e), RunStatus::Failed, errorKindOf(e));
}

RunLife::End RunLife::endInterrupted(const std::string& where) {
  return end(interruptedLine(where), RunStatus::Interrupted, ErrorKind::Stopped);
}

std::string RunLife::interruptedLine(const std::string& where) {
  return std::string("interrupted by ") + Cancellation::signalName() + where;
}

}  // namespace budget_slam::runs
