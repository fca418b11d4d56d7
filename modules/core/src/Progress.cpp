#include "budget_slam/core/Progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace budget_slam {
namespace {

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

constexpr double kBarEvery = 0.1;       ///< [s] between two redraws of the bar
constexpr double kCallbackEvery = 0.2;  ///< [s] between two calls of the callback

}  // namespace

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long long>(std::llround(seconds));
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
  return text;
}

ProgressReporter::ProgressReporter(std::ostream& out, std::string task, ProgressSettings settings,
                                   Clock clock)
    : out_(out),
      task_(std::move(task)),
      settings_(std::move(settings)),
      clock_(clock ? std::move(clock) : Clock(steadySeconds)) {
  start_ = clock_();
  last_line_ = start_;
}

ProgressReporter::~ProgressReporter() {
  if (bar_drawn_) out_ << "\r\x1b[K" << std::flush;
}

ProgressSnapshot ProgressReporter::snapshot(double fraction, std::size_t steps_done,
                                            std::size_t steps_total, const std::string& detail,
                                            double eta_s) const {
  ProgressSnapshot s;
  s.task = task_;
  s.fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  s.steps_done = steps_done;
  s.steps_total = steps_total;
  s.elapsed_s = std::max(0.0, clock_() - start_);
  if (s.elapsed_s > 0) s.steps_per_s = steps_done / s.elapsed_s;
  if (std::isfinite(eta_s) && eta_s >= 0)
    s.eta_s = eta_s;
  else if (s.fraction > 0)
    s.eta_s = s.elapsed_s * (1 - s.fraction) / s.fraction;
  s.detail = detail;
  return s;
}

std::string ProgressReporter::line(const ProgressSnapshot& s) {
  std::string t = s.task + " " + std::to_string(static_cast<int>(std::floor(100 * s.fraction))) +
                  "%, " + std::to_string(s.steps_done);
  if (s.steps_total) t += " of " + std::to_string(s.steps_total);
  t += " steps";
  if (std::isfinite(s.steps_per_s))
    t += ", " + std::to_string(static_cast<long long>(std::llround(s.steps_per_s))) + " steps/s";
  t += ", elapsed " + formatDuration(s.elapsed_s) + ", ETA " + formatDuration(s.eta_s);
  if (!s.detail.empty()) t += " (" + s.detail + ")";
  return t;
}

void ProgressReporter::update(double fraction, std::size_t steps_done, std::size_t steps_total,
                              const std::string& detail, double eta_s) {
  last_steps_done_ = steps_done, last_steps_total_ = steps_total, last_detail_ = detail;
  const bool bar = settings_.style == ProgressSettings::Style::Bar;
  const bool lines =
      settings_.style == ProgressSettings::Style::Lines && settings_.line_every_s > 0;
  if (!bar && !lines && !settings_.callback) return;
  const double now = clock_();
  const bool bar_due = bar && now - last_bar_ >= kBarEvery;
  const bool line_due = lines && now - last_line_ >= settings_.line_every_s;
  const bool callback_due = settings_.callback && now - last_callback_ >= kCallbackEvery;
  if (!bar_due && !line_due && !callback_due) return;
  const ProgressSnapshot s = snapshot(fraction, steps_done, steps_total, detail, eta_s);
  if (bar_due) {
    last_bar_ = now;
    bar_drawn_ = true;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(std::round(s.fraction * kWidth));
    out_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '.') << "] "
         << line(s) << "\x1b[K" << std::flush;
  }
  if (line_due) {
    // Lines keep their cadence from the start, so a slow step does not shift every later line.
    last_line_ += settings_.line_every_s * std::floor((now - last_line_) / settings_.line_every_s);
    out_ << "budget-slam: " << line(s) << "\n" << std::flush;
  }
  if (callback_due) {
    last_callback_ = now;
    settings_.callback(s);
  }
}

void ProgressReporter::finish(bool completed) {
  if (finished_) return;
  finished_ = true;
  if (bar_drawn_) out_ << "\r\x1b[K" << std::flush;
  bar_drawn_ = false;
  if (completed && settings_.callback) {
    ProgressSnapshot s = snapshot(1.0, last_steps_done_, last_steps_total_, last_detail_);
    s.finished = true;
    settings_.callback(s);
  }
}

}  // namespace budget_slam
