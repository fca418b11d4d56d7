#pragma once
#include <Eigen/Core>
#include <vector>

#include "budget_slam/core/Se2.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// One reading of a gathered step, brought into the robot frame of the latest step by the
/// odometry in between.
struct LocalReading {
  StepIndex step = 0;
  LandmarkId id = kNoLandmarkId;                         ///< the sensor's id, kNoLandmarkId if none
  Eigen::Vector2d z = Eigen::Vector2d::Zero();           ///< range [m], bearing [rad]
  Pose2 sensor = Pose2::Zero();                          ///< the sensor when it read, latest frame
  Eigen::Matrix3d sensor_cov = Eigen::Matrix3d::Zero();  ///< from the odometry in between
  Eigen::Vector2d point = Eigen::Vector2d::Zero();       ///< the landmark it puts, latest frame [m]
  Eigen::Matrix2d point_cov = Eigen::Matrix2d::Zero();   ///< reading noise and odometry [m^2]
};

/// The steps gathered since the robot woke up: their readings and the odometry between them.
class ReadingWindow {
 public:
  ReadingWindow(const ReadingNoise& noise, const WakeUpOptions& options);

  /// One more step: its odometry (the motion that led to it; none: zero motion with
  /// [WakeUp] no_odometry_std_*) and its bearing-range readings (none: a step without readings).
  void add(const Step& step);

  std::size_t steps() const { return steps_.size(); }
  /// Index of the latest step added.
  StepIndex latest() const;
  /// The longest range the sensor reports, over the steps gathered (0: unknown) [m].
  double maxRange() const { return max_range_; }
  const ReadingNoise& noise() const { return noise_; }

  /// Every reading gathered, in the robot frame of the latest step, in step order. The pose of
  /// an earlier step in that frame is the inverse odometry composed backwards, its covariance
  /// propagated to first order (steps' odometry independent).
  std::vector<LocalReading> readings() const;

 private:
  struct Gathered {
    StepIndex index = 0;
    Pose2 odometry = Pose2::Zero();  ///< motion from the previous step, in its frame
    Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
    Pose2 sensor = Pose2::Zero();  ///< sensor pose on the robot (x, y, yaw)
    std::vector<RangeBearingReading> readings;
  };
  ReadingNoise noise_;
  WakeUpOptions options_;
  std::vector<Gathered> steps_;
  double max_range_ = 0;
};

}  // namespace budget_slam::wakeup
