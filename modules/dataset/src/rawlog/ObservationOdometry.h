#pragma once
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>

#include <optional>

namespace budget_slam::dataset::rawlog {

/// Odometry of an observations-format rawlog (MRPT's other format: sensory frames or bare
/// observations, no actions), turned into the action each step would carry in the
/// actions-observations format, the way MRPT's tools convert one format into the other
/// (RawLogViewer's "convert to sensory frames", MonteCarloLocalization_App): the robot moves by
/// the pose increment between the CObservationOdometry reading a step uses and the one the step
/// before used (CPose2D inverse composition, new ⊖ previous), with the covariance that
/// CActionRobotMovement2D::computeFromOdometry gives under MRPT's default Gaussian motion model
/// (TMotionModelOptions(): minStdXY 0.01 m, minStdPHI 0.2 deg, a1 0.01, a2 0.0573, a3 1 deg,
/// a4 0.05). The first reading only sets the reference; a step with no new reading has no action.
class ObservationOdometry {
 public:
  /// An absolute odometry reading.
  void reading(const mrpt::obs::CObservationOdometry& odo);
  /// The action of the next step: one CActionRobotMovement2D with the increment since the last
  /// reading used, or an empty collection when no reading came since (or only the first).
  mrpt::obs::CActionCollection::Ptr actionForStep();

 private:
  std::optional<mrpt::poses::CPose2D> used_;    // reading the previous step moved to
  std::optional<mrpt::poses::CPose2D> latest_;  // newest reading not used yet
  mrpt::Clock::time_point latest_t_;
};

}  // namespace budget_slam::dataset::rawlog
