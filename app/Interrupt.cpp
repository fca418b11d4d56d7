#include "Interrupt.h"

#include <csignal>

namespace budget_slam::app {
namespace {
std::atomic<int> g_signal{0};
void (*g_previous_int)(int) = SIG_DFL;
void (*g_previous_term)(int) = SIG_DFL;
extern "C" void onSignal(int sig) { g_signal.store(sig); }
}  // namespace

InterruptGuard::InterruptGuard() {
  g_previous_int = std::signal(SIGINT, onSignal);
  g_previous_term = std::signal(SIGTERM, onSignal);
}
InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, g_previous_int);
  std::signal(SIGTERM, g_previous_term);
}
bool InterruptGuard::requested() { return g_signal.load() != 0; }
void InterruptGuard::request() { g_signal.store(SIGINT); }
void InterruptGuard::clear() { g_signal.store(0); }
const char* InterruptGuard::what() { return g_signal.load() == SIGTERM ? "SIGTERM" : "Ctrl-C"; }

}  // namespace budget_slam::app
