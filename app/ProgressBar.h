#pragma once
#include <chrono>
#include <ostream>
#include <string>

namespace budget_slam::app {

/// A one-line progress bar redrawn in place, shown only when the stream is a terminal.
class ProgressBar {
 public:
  ProgressBar(std::ostream& out, bool enabled);
  /// fraction in [0,1]; redraws at most 10 times a second.
  void update(double fraction, const std::string& text);
  void done();

 private:
  std::ostream& out_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

/// True when stderr is a terminal.
bool stderrIsTerminal();

}  // namespace budget_slam::app
