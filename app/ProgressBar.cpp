#include "ProgressBar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace budget_slam::app {

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::ostream& out, bool enabled) : out_(out), enabled_(enabled) {}

void ProgressBar::update(double fraction, const std::string& text) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  drawn_ = true;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(std::round(std::clamp(fraction, 0.0, 1.0) * kWidth));
  out_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '.') << "] "
       << static_cast<int>(std::round(100 * std::clamp(fraction, 0.0, 1.0))) << "% " << text
       << "\x1b[K" << std::flush;
}

void ProgressBar::done() {
  if (enabled_ && drawn_) out_ << "\r\x1b[K" << std::flush;
  drawn_ = false;
}

}  // namespace budget_slam::app
