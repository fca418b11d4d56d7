#include "budget_slam/core/Cancellation.h"

#include <atomic>
#include <csignal>
#include <string>

namespace budget_slam {
namespace {
// Lock-free, so setting it from a signal handler is well defined.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the stop flag must be signal-safe");
}  // namespace

void Cancellation::request(int signal) noexcept {
  // The first request names the stop: a SIGTERM after Ctrl-C does not rename it.
  int none = 0;
  g_signal.compare_exchange_strong(none, signal == 0 ? SIGINT : signal);
}
void Cancellation::clear() noexcept { g_signal.store(0); }
bool Cancellation::requested() noexcept { return g_signal.load(std::memory_order_relaxed) != 0; }
int Cancellation::signal() noexcept { return g_signal.load(); }
const char* Cancellation::signalName() noexcept {
  return g_signal.load() == SIGTERM ? "SIGTERM" : "Ctrl-C";
}

void Cancellation::check() {
  if (requested()) throw Interrupted(std::string("interrupted by ") + signalName());
}

}  // namespace budget_slam
