#pragma once
#include "budget_slam/core/Error.h"

namespace budget_slam {

/// The run was asked to stop (Ctrl-C, SIGTERM) while it was inside a long computation. Caught
/// by the application, which writes every output and exits with status `interrupted`.
class Interrupted : public Error {
 public:
  using Error::Error;
};

/// A process-wide stop request: the application's signal handler raises it, and the long loops
/// (the reading loops, the steps, active minimization's greedy sequence, the graph solver's
/// iterations, the budget manager's drop loops, compare's runs) poll it, so that a signal ends a
/// run within a second wherever it is. One flag for the whole process: compare's worker threads
/// see the same request.
class Cancellation {
 public:
  /// Raises the flag. Async-signal-safe (one lock-free atomic store): a signal handler calls it.
  static void request(int signal) noexcept;
  static void clear() noexcept;
  static bool requested() noexcept;
  /// The signal that raised the flag (SIGINT for request() from code), 0 when not requested.
  static int signal() noexcept;
  /// "Ctrl-C" or "SIGTERM", for messages.
  static const char* signalName() noexcept;
  /// Throws Interrupted("interrupted by Ctrl-C") when the flag is up. Cheap: call it once an
  /// iteration of any loop that can run for more than a few milliseconds.
  static void check();
};

}  // namespace budget_slam
