#pragma once
#include <mrpt/math/TPose3D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Pose2.h"

namespace budget_slam {

/// Odometry increment of one step: the mean of MRPT's CActionRobotMovement2D pose change,
/// expressed in the frame of the previous robot pose, with its 3x3 covariance
/// (x [m], y [m], yaw [rad]).
struct OdometryIncrement {
  Pose2 mean;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

/// One landmark reading of a CObservationBearingRange.
struct RangeBearingReading {
  LandmarkId id = kNoLandmarkId;  ///< sensor landmark ID, kNoLandmarkId when absent
  double range = 0;               ///< [m]
  double yaw = 0;                 ///< bearing in the sensor frame [rad]
  double pitch = 0;               ///< [rad], 0 in 2D
};

/// The bearing-range scan of one step, in the sensor frame.
struct RangeBearingScan {
  mrpt::math::TPose3D sensor_pose_on_robot;  ///< sensor pose in the robot frame
  double min_range = 0;                      ///< [m]
  double max_range = 0;                      ///< [m]
  double fov_yaw = 0;                        ///< total horizontal field of view [rad]
  double std_range = 0;                      ///< noise the rawlog states, informative only [m]
  double std_yaw = 0;                        ///< noise the rawlog states, informative only [rad]
  std::vector<RangeBearingReading> readings;
};

/// One action-observation pair of a rawlog, parsed once and shared read-only by every run.
/// `odometry` and `scan` are what every module reads. `action` and `frame` are the rawlog's own
/// MRPT objects, read only by the EKF backend so that it feeds MRPT exactly what MRPT's kf-slam
/// would (per-reading covariances and all); nothing modifies them. When `scan` holds fewer
/// readings than the frame (core/StepFilter.h), `scan` is right: the EKF restricts the frame's
/// observation to them (ekf::mrptStepInput).
struct Step {
  StepIndex index = 0;
  double t = 0;  ///< timestamp [s]; the step index when the rawlog has no usable timestamps
  std::optional<OdometryIncrement> odometry;  ///< none: no CActionRobotMovement2D in the action
  std::optional<RangeBearingScan> scan;  ///< none: no CObservationBearingRange (prediction only)
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
};

}  // namespace budget_slam
