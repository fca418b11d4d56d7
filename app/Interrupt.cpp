#include "Interrupt.h"

#include <csignal>

#include "budget_slam/core/Cancellation.h"

namespace budget_slam::app {
namespace {
void (*g_previous_int)(int) = SIG_DFL;
void (*g_previous_term)(int) = SIG_DFL;
void (*g_previous_xfsz)(int) = SIG_DFL;
extern "C" void onSignal(int sig) { Cancellation::request(sig); }
}  // namespace

InterruptGuard::InterruptGuard() {
  g_previous_int = std::signal(SIGINT, onSignal);
  g_previous_term = std::signal(SIGTERM, onSignal);
  g_previous_xfsz = std::signal(SIGXFSZ, SIG_IGN);
}
InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, g_previous_int);
  std::signal(SIGTERM, g_previous_term);
  std::signal(SIGXFSZ, g_previous_xfsz);
}
bool InterruptGuard::requested() { return Cancellation::requested(); }
void InterruptGuard::request() { Cancellation::request(SIGINT); }
void InterruptGuard::clear() { Cancellation::clear(); }
const char* InterruptGuard::what() { return Cancellation::signalName(); }

}  // namespace budget_slam::app
