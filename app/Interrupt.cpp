#include "Interrupt.h"

#include <csignal>

namespace budget_slam::app {
namespace {
std::atomic<bool> g_interrupted{false};
void (*g_previous)(int) = SIG_DFL;
extern "C" void onSigint(int) { g_interrupted.store(true); }
}  // namespace

InterruptGuard::InterruptGuard() { g_previous = std::signal(SIGINT, onSigint); }
InterruptGuard::~InterruptGuard() { std::signal(SIGINT, g_previous); }
bool InterruptGuard::requested() { return g_interrupted.load(); }
void InterruptGuard::request() { g_interrupted.store(true); }
void InterruptGuard::clear() { g_interrupted.store(false); }

}  // namespace budget_slam::app
