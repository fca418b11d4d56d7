#pragma once
#include <atomic>

namespace budget_slam::app {

/// Ctrl-C (SIGINT) and SIGTERM (kill, timeout, a batch scheduler's time limit) end a run like an
/// error, with status `interrupted` and every output written: the signal only raises this flag,
/// and the step loops check it between steps.
class InterruptGuard {
 public:
  InterruptGuard();   ///< installs the SIGINT and SIGTERM handlers
  ~InterruptGuard();  ///< restores the previous one
  static bool requested();
  static void request();  ///< as if Ctrl-C was pressed (tests)
  static void clear();
  /// "Ctrl-C" or "SIGTERM", for messages.
  static const char* what();
};

}  // namespace budget_slam::app
