#pragma once
// How far a run, a compare or a localization has come, told to whoever watches (docs/OUTPUTS.md
// "Progress"): a bar redrawn in place on a terminal, a line every few seconds anywhere else (a
// pipe, a log file, a batch scheduler's log), and a callback (Python's progress=).
#include <cstddef>
#include <functional>
#include <limits>
#include <ostream>
#include <string>

namespace budget_slam {

/// One report of progress.
struct ProgressSnapshot {
  std::string task;             ///< "run", "compare", "reading the rawlog", "localize"
  double fraction = 0;          ///< of the task done, in [0, 1]
  std::size_t steps_done = 0;   ///< steps processed (compare: over all its runs)
  std::size_t steps_total = 0;  ///< 0 while not known (run reads the rawlog as it goes)
  double elapsed_s = 0;         ///< since the task started [s]
  double steps_per_s = std::numeric_limits<double>::quiet_NaN();
  double eta_s = std::numeric_limits<double>::quiet_NaN();  ///< time left [s], NaN until known
  std::string detail;     ///< "step 120, 50 landmarks", "3/8 runs done"
  bool finished = false;  ///< the last report: the task is done
};

using ProgressCallback = std::function<void(const ProgressSnapshot&)>;

/// Where progress goes.
struct ProgressSettings {
  enum class Style {
    None,   ///< nothing on the stream (--quiet)
    Bar,    ///< a bar redrawn in place, at most 10 times a second (a terminal)
    Lines,  ///< a line every `line_every_s` (not a terminal)
  };
  Style style = Style::None;
  double line_every_s = 5;  ///< [s]; 0: no lines
  /// Called at most 5 times a second, and once more at the end (finished = true) when the task
  /// completed; may throw, which ends the task (the caller's choice how).
  ProgressCallback callback;
};

/// True when the process's stderr is a terminal (a bar fits there; elsewhere, lines).
bool stderrIsTerminal();

/// "0:07", "12:34", "1:02:03"; "?" for a time not known.
std::string formatDuration(double seconds);

/// One task's progress reports (not thread-safe: one thread updates it).
class ProgressReporter {
 public:
  using Clock = std::function<double()>;  ///< seconds, monotonic
  ProgressReporter(std::ostream& out, std::string task, ProgressSettings settings,
                   Clock clock = {});
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// `fraction` in [0, 1] of the task; `steps_total` 0 when not known. The ETA is `eta_s` [s]
  /// when the caller knows better (compare: from each run's own pace), else the elapsed time
  /// scaled by the fraction left.
  void update(double fraction, std::size_t steps_done, std::size_t steps_total,
              const std::string& detail, double eta_s = std::numeric_limits<double>::quiet_NaN());
  /// The task ended: the bar is cleared; when `completed`, the callback hears fraction 1 once.
  void finish(bool completed);

  /// The snapshot `update` would report now (tests, and the line and bar text).
  ProgressSnapshot snapshot(double fraction, std::size_t steps_done, std::size_t steps_total,
                            const std::string& detail,
                            double eta_s = std::numeric_limits<double>::quiet_NaN()) const;
  /// "run 42%, 2950 of 6969 steps, 1520 steps/s, ETA 0:03 (detail)".
  static std::string line(const ProgressSnapshot& s);

 private:
  std::ostream& out_;
  std::string task_;
  ProgressSettings settings_;
  Clock clock_;
  double start_ = 0, last_bar_ = -1e300, last_line_ = 0, last_callback_ = -1e300;
  bool bar_drawn_ = false, finished_ = false;
  std::size_t last_steps_done_ = 0, last_steps_total_ = 0;
  std::string last_detail_;
};

}  // namespace budget_slam
