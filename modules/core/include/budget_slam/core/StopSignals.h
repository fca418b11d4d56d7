#pragma once

namespace budget_slam {

/// The signals of budget-slam, budget-convert and budget-simulate (docs/RELIABILITY.md
/// "Signals"). While one lives:
///  - SIGINT (Ctrl-C) and SIGTERM (kill, a time-out, a batch scheduler's time limit) raise the
///    process-wide stop request (core/Cancellation.h), which the reading, step and writing loops
///    poll: the program ends as `interrupted` with every output written, one line on stderr and
///    exit code 130. Every further SIGINT or SIGTERM only raises it again: a second Ctrl-C never
///    kills the process in the middle of a file;
///  - SIGPIPE is ignored: a closed stdout (`| head`) is a failed write, reported, not a kill;
///  - SIGXFSZ is ignored: a file-size limit (ulimit -f) makes a write fail with EFBIG, reported
///    like a full disk, instead of killing the process mid-file.
/// The handlers are installed with sigaction() and stay installed however many signals arrive.
/// Nested guards share the first one's handlers.
class StopSignals {
 public:
  /// `restore`: the destructor puts the previous handlers back (the library inside another
  /// program: Python's module, tests). main() keeps its guard for the life of the process, so that
  /// a signal during start-up or exit ends the program as cleanly as one during a run.
  explicit StopSignals(bool restore = true);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// True while a guard is installed (an inner guard then leaves the stop request as it is: a
  /// signal that came during start-up still counts).
  static bool installed();

 private:
  bool outermost_ = false, restore_ = true;
};

}  // namespace budget_slam
