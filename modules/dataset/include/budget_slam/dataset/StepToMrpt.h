#pragma once
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/system/datetime.h>

#include <optional>

#include "budget_slam/core/Step.h"

namespace budget_slam::dataset {

/// MRPT timestamp of `t` seconds since the Unix epoch. t must be > 0 (0 is MRPT's
/// INVALID_TIMESTAMP).
mrpt::system::TTimeStamp toTimestamp(double t);

/// A CActionCollection holding one CActionRobotMovement2D whose poseChange is a
/// CPosePDFGaussian(mean, cov), the object MRPT's kf-slam takes through
/// getBestMovementEstimation()->poseChange. estimationMethod is emScan2DMatching: with emOdometry
/// MRPT serializes only the raw increment and rebuilds the covariance from its motion model on
/// load, which would lose a full covariance.
mrpt::obs::CActionCollection::Ptr makeAction(const OdometryIncrement& odometry, double t);

/// A CSensoryFrame holding one CObservationBearingRange (label "BEARING_RANGE"): a landmarkID
/// per reading (INVALID_LANDMARK_ID for kNoLandmarkId), min/max range, fieldOfView_yaw,
/// sensorLocationOnRobot and sensor_std_range / sensor_std_yaw. Throws InputError for an id that
/// does not fit MRPT's int32 or appears twice in the scan (MRPT refuses to serialize those).
mrpt::obs::CSensoryFrame::Ptr makeFrame(const RangeBearingScan& scan, double t);

/// A complete Step: the MRPT objects above (an empty CActionCollection / CSensoryFrame where the
/// optional is empty) and the parsed fields rounded to the precision MRPT stores (float for
/// readings, limits and stds), so that reading the written rawlog gives this Step back.
Step makeStep(StepIndex index, double t, const std::optional<OdometryIncrement>& odometry,
              const std::optional<RangeBearingScan>& scan);

}  // namespace budget_slam::dataset
