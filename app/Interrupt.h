#pragma once
#include <atomic>

namespace budget_slam::app {

/// Ctrl-C ends a run like an error, with status `interrupted` and every output written: SIGINT
/// only raises this flag, and the step loops check it between steps.
class InterruptGuard {
 public:
  InterruptGuard();   ///< installs the SIGINT handler
  ~InterruptGuard();  ///< restores the previous one
  static bool requested();
  static void request();  ///< as if Ctrl-C was pressed (tests)
  static void clear();
};

}  // namespace budget_slam::app
