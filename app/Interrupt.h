#pragma once
#include <atomic>

namespace budget_slam::app {

/// Ctrl-C (SIGINT) and SIGTERM (kill, timeout, a batch scheduler's time limit) end a run like an
/// error, with status `interrupted` and every output written: the signal only raises the
/// process-wide stop request (core/Cancellation.h), which the step loops check between steps and
/// the long computations inside a step or the end phase poll (they throw Interrupted).
/// While installed, SIGXFSZ is ignored too: a file-size limit (ulimit -f) then makes a write fail
/// with EFBIG, reported like a full disk, instead of killing the process mid-file.
class InterruptGuard {
 public:
  InterruptGuard();   ///< installs the SIGINT and SIGTERM handlers
  ~InterruptGuard();  ///< restores the previous ones
  static bool requested();
  static void request();  ///< as if Ctrl-C was pressed (tests)
  static void clear();
  /// "Ctrl-C" or "SIGTERM", for messages.
  static const char* what();
};

}  // namespace budget_slam::app
