#pragma once
#include <cstddef>
#include <memory>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/wakeup/CorrespondenceSearch.h"
#include "budget_slam/wakeup/PoseFit.h"
#include "budget_slam/wakeup/ReadingWindow.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// Where the wake-up stands.
enum class WakeUpStatus {
  Found,      ///< the robot is on the map: `pose` holds
  NotFound,   ///< no pose yet (see WakeUpReason)
  Ambiguous,  ///< search: another pose, far from the best, agrees nearly as well
};

/// Why the robot is not found (WakeUpReason::None when it is, or when ambiguous).
enum class WakeUpReason {
  None,
  TooFewLandmarks,  ///< fewer map landmarks seen than [WakeUp] min_landmarks (search_min_landmarks)
  Degenerate,       ///< the landmarks seen do not fix the pose (coincident, or one point)
  Inconsistent,     ///< no pose agrees with enough of the readings
  TooUncertain,     ///< a pose, but its standard deviation is above [WakeUp] max_std_*
};

const char* statusName(WakeUpStatus s);  ///< "found", "not_found", "ambiguous"
const char* reasonName(WakeUpReason r);  ///< "", "too_few_landmarks", "degenerate", ...

/// The outcome of a wake-up attempt.
struct WakeUpResult {
  WakeUpStatus status = WakeUpStatus::NotFound;
  WakeUpReason reason = WakeUpReason::TooFewLandmarks;
  bool by_ids = false;  ///< readings paired with the map by id (else by search)
  /// The robot at `step` (the latest step used) in the map's frame, and its covariance; set when
  /// found (and, for TooUncertain, the uncertain estimate).
  PoseEstimate pose;
  StepIndex step = 0;
  std::size_t steps_used = 0;  ///< steps whose readings were gathered
  std::size_t readings = 0;    ///< readings gathered
  std::size_t inliers = 0;     ///< readings that agree with the pose (within [WakeUp] gate_chi2)
  std::size_t landmarks = 0;   ///< distinct map landmarks among them
  std::size_t hypotheses = 0;  ///< search: hypotheses scored
  std::size_t runner_up = 0;   ///< search: landmarks agreeing with the best other pose
  /// Search: the best pose's and its rival's score (agreeing landmarks - [WakeUp] miss_weight x
  /// landmarks in view that no reading shows); no rival: 0.
  double score = 0, runner_up_score = 0;
};

/// Finds the robot on a saved landmark map from the readings of its first steps, with no start
/// pose (docs/ALGORITHMS.md "Waking up on a saved map"). Feed it one step at a time; after each it
/// tries with every reading gathered so far. With landmark ids: closed-form rigid fit over the id
/// pairs, then Gauss-Newton on the range-bearing model, readings beyond the gate dropped one at a
/// time. Without: hypotheses over pairs of readings and pairs of landmarks (searchPose), the best
/// one refined the same way, refused when not clearly better than the best other pose.
class GlobalLocalizer {
 public:
  /// `map`: the saved landmarks (ids, means, marginal covariances).
  GlobalLocalizer(std::vector<LandmarkView> map, const WakeUpOptions& options,
                  const ReadingNoise& noise);

  /// Gathers `step` and tries. Once found, or once [WakeUp] max_steps steps are gathered,
  /// finished() is true and further steps change nothing.
  const WakeUpResult& add(const Step& step);
  const WakeUpResult& result() const { return result_; }
  bool finished() const;

 private:
  WakeUpResult attempt();
  WakeUpResult byIds(const std::vector<LocalReading>& readings);
  WakeUpResult bySearch(const std::vector<LocalReading>& readings);
  /// Refines from `start` over `pairs`, dropping the worst reading while any is beyond the gate,
  /// and judges the outcome. `start` none: the closed-form fit of the remaining pairs.
  WakeUpResult refineAndJudge(std::optional<Pose2> start, const std::vector<LocalReading>& r,
                              std::vector<Pairing> pairs, std::size_t min_landmarks);

  WakeUpOptions options_;
  ReadingNoise noise_;
  MapIndex index_;
  std::unordered_map<LandmarkId, std::size_t> by_id_;
  ReadingWindow window_;
  std::mt19937_64 rng_;
  WakeUpResult result_;
};

/// Runs a GlobalLocalizer over `steps` until it finishes (or the steps run out).
WakeUpResult wakeUp(const std::vector<LandmarkView>& map, const std::vector<Step>& steps,
                    const WakeUpOptions& options, const ReadingNoise& noise);

}  // namespace budget_slam::wakeup
