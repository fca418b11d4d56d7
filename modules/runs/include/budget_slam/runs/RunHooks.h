#pragma once
// How a caller follows a command (run, compare, localize): progress, steps, notes, warnings.
#include <functional>
#include <ostream>
#include <string>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Progress.h"

namespace budget_slam::runs {

/// How the caller follows a run: where progress goes, what it hears after each step and before
/// the end phase, and where notes go (a note is one line; the caller decides whether to show it).
struct RunHooks {
  std::ostream* progress_out = nullptr;  ///< the progress bar or lines (none: no progress)
  ProgressSettings progress;
  std::function<void(StepIndex)> on_step;        ///< after each step (tests press Ctrl-C there)
  std::function<void()> on_end_phase;            ///< once the steps are done, before the end phase
  std::function<void(const std::string&)> note;  ///< "<folder> held an earlier run; ...", ...
  /// A warning as it arises (one line without "warning: "): a sidecar key over the ini's, fewer
  /// threads than asked, a failed shadow reducer (runs::run and runs::compare; runSlam hands its
  /// warnings back in RunReport::warnings instead).
  std::function<void(const std::string&)> warning;
};

}  // namespace budget_slam::runs
