#include "budget_slam/wakeup/WakeUpRun.h"

#include <chrono>
#include <cmath>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Pose2.h"

namespace budget_slam::wakeup {

ReadingNoise readingNoiseOf(const mrpt::config::CConfigFileBase& ini) {
  ReadingNoise noise;
  noise.std_range = ini.read_double("RangeBearingKFSLAM", "std_sensor_range", 0.1);
  noise.std_bearing = ini.read_double("RangeBearingKFSLAM", "std_sensor_yaw_deg", 0.5) * M_PI / 180;
  return noise;
}

std::string WakeUpRun::whyNotFound(const WakeUpOptions& options) const {
  if (found()) return "";
  const WakeUpResult& r = result;
  std::string why = "the robot was not found on the map in " + std::to_string(steps_read) +
                    " step" + (steps_read == 1 ? "" : "s") + " (";
  if (r.status == WakeUpStatus::Ambiguous) {
    why += "ambiguous: " + std::to_string(r.landmarks) + " landmarks agree with the best pose, " +
           std::to_string(r.runner_up) + " with another";
  } else {
    why += std::string(statusName(r.status)) + ", " + reasonName(r.reason);
    const std::size_t needed = r.by_ids ? options.min_landmarks : options.search_min_landmarks;
    switch (r.reason) {
      case WakeUpReason::TooFewLandmarks:
        why += ": " + std::to_string(r.landmarks) + " landmark(s), " + std::to_string(needed) +
               " needed";
        break;
      case WakeUpReason::TooUncertain:
        why += ": standard deviation above [WakeUp] max_std_xy / max_std_yaw_deg";
        break;
      case WakeUpReason::Inconsistent:
        why += ": no pose agrees with enough of the readings";
        break;
      case WakeUpReason::Degenerate:
        why += ": the landmarks seen do not fix the pose";
        break;
      case WakeUpReason::None:
        break;
    }
  }
  return why + ")";
}

WakeUpRun wakeUpOver(const std::vector<LandmarkView>& map, const std::function<const Step*()>& next,
                     const WakeUpOptions& options, const ReadingNoise& noise) {
  const auto t0 = std::chrono::steady_clock::now();
  GlobalLocalizer localizer(map, options, noise);
  WakeUpRun run;
  // A stop request (Ctrl-C, SIGTERM) ends the wake-up between steps and inside each attempt's
  // search (CorrespondenceSearch.cpp) with Interrupted, never with a result: a traversal that
  // ended because the stop came is not a robot "not found".
  while (!localizer.finished()) {
    Cancellation::check();
    const Step* step = next();
    if (!step) break;
    localizer.add(*step);
    ++run.steps_read;
  }
  Cancellation::check();
  run.result = localizer.result();
  run.wall_ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

WakeUpError wakeUpError(const PoseEstimate& found, const Pose2& truth) {
  return {std::hypot(found.mean.x - truth.x, found.mean.y - truth.y),
          std::abs(wrapAngle(found.mean.phi - truth.phi)) * 180 / M_PI};
}

}  // namespace budget_slam::wakeup
