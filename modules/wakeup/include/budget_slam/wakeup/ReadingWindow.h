#pragma once
#include <Eigen/Core>
#include <vector>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// One reading of a gathered step, brought into the robot frame of the latest step by the
/// odometry in between.
struct LocalReading {
  StepIndex step = 0;
  LandmarkId id = kNoLandmarkId;                         ///< the sensor's id, kNoLandmarkId if none
  Eigen::Vector2d z = Eigen::Vector2d::Zero();           ///< range [m], bearing [rad]
  Pose2 sensor;                                          ///< the sensor when it read, latest frame
  Eigen::Matrix3d sensor_cov = Eigen::Matrix3d::Zero();  ///< from the odometry in between
  Eigen::Vector2d point = Eigen::Vector2d::Zero();       ///< the landmark it puts, latest frame [m]
  Eigen::Matrix2d point_cov = Eigen::Matrix2d::Zero();   ///< reading noise and odometry [m^2]
};

/// What the sensor could see at one gathered step: its pose in the robot frame of the latest step
/// and its limits (the negative evidence of the search: a map landmark well inside them that no
/// reading explains).
struct SensorView {
  StepIndex step = 0;
  Pose2 sensor;                         ///< latest robot frame
  double min_range = 0, max_range = 0;  ///< [m]; max_range 0: unknown
  double fov = 0;                       ///< total horizontal field of view [rad]
};

/// One gathered step as the joint fit of the window reads it (fitWindow, WindowFit.h).
struct WindowStep {
  StepIndex index = 0;
  /// The motion from the previous gathered step, in its frame, and its covariance (the first
  /// step's leads from outside the window and is not used).
  Pose2 odometry;
  Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
  Pose2 on_robot;  ///< the sensor's pose on the robot
  Pose2 pose;      ///< the robot in the latest robot frame, by the odometry
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
  /// The sensor of every gathered step that had a bearing-range scan, in step order.
  std::vector<SensorView> views() const;
  /// Every gathered step: its odometry, its sensor on the robot and its pose in the latest robot
  /// frame, in step order.
  std::vector<WindowStep> gathered() const;

 private:
  struct Gathered {
    StepIndex index = 0;
    Pose2 odometry;  ///< motion from the previous step, in its frame
    Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
    Pose2 sensor;          ///< sensor pose on the robot (x, y, yaw)
    bool scanned = false;  ///< the step had a bearing-range scan
    double min_range = 0, max_range = 0, fov = 0;
    std::vector<RangeBearingReading> readings;
  };
  /// Each step's robot pose in the latest robot frame and its covariance (the inverse odometry
  /// composed backwards, first-order propagation), in step order.
  std::vector<std::pair<Pose2, Eigen::Matrix3d>> chain() const;
  ReadingNoise noise_;
  WakeUpOptions options_;
  std::vector<Gathered> steps_;
  double max_range_ = 0;
};

}  // namespace budget_slam::wakeup
