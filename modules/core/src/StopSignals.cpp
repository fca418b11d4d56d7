#include "budget_slam/core/StopSignals.h"

#include <csignal>

#include "budget_slam/core/Cancellation.h"

namespace budget_slam {
namespace {

int g_depth = 0;  ///< guards alive (installed and removed on the main thread)
struct sigaction g_previous[4];
constexpr int kSignals[4] = {SIGINT, SIGTERM, SIGPIPE, SIGXFSZ};

extern "C" void onStopSignal(int sig) { Cancellation::request(sig); }

}  // namespace

StopSignals::StopSignals(bool restore) : restore_(restore) {
  if (g_depth++ > 0) return;
  outermost_ = true;
  for (int i = 0; i < 4; ++i) {
    struct sigaction sa {};
    sigemptyset(&sa.sa_mask);
    // SA_RESTART: a read or write under way when the signal comes goes on; the loops poll the
    // flag. No SA_RESETHAND: the next signal finds the same handler.
    sa.sa_flags = SA_RESTART;
    sa.sa_handler = (kSignals[i] == SIGINT || kSignals[i] == SIGTERM) ? onStopSignal : SIG_IGN;
    sigaction(kSignals[i], &sa, &g_previous[i]);
  }
}

StopSignals::~StopSignals() {
  --g_depth;
  if (!outermost_ || !restore_) return;
  for (int i = 0; i < 4; ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
}

bool StopSignals::installed() { return g_depth > 0; }

}  // namespace budget_slam
