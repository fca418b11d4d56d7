#include "budget_slam/dataset/StepToMrpt.h"

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cmath>
#include <limits>
#include <set>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/MrptPose.h"

namespace budget_slam::dataset {
mrpt::system::TTimeStamp toTimestamp(double t) {
  if (!(t > 0) || !std::isfinite(t))
    throw InputError("timestamp " + std::to_string(t) + " s is not a positive finite time");
  return mrpt::Clock::fromDouble(t);
}

mrpt::obs::CActionCollection::Ptr makeAction(const OdometryIncrement& odometry, double t) {
  mrpt::obs::CActionRobotMovement2D move;
  // emScan2DMatching makes MRPT serialize the Gaussian itself (see the header).
  move.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
  const mrpt::poses::CPose2D mean(odometry.mean.x, odometry.mean.y, odometry.mean.phi);
  mrpt::math::CMatrixDouble33 cov;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) cov(r, c) = 0.5 * (odometry.cov(r, c) + odometry.cov(c, r));
  move.poseChange = mrpt::poses::CPosePDFGaussian::Create(mean, cov);
  move.rawOdometryIncrementReading = mean;
  move.timestamp = toTimestamp(t);
  auto action = mrpt::obs::CActionCollection::Create();
  action->insert(move);
  return action;
}

mrpt::obs::CSensoryFrame::Ptr makeFrame(const RangeBearingScan& scan, double t) {
  auto obs = mrpt::obs::CObservationBearingRange::Create();
  obs->sensorLabel = "BEARING_RANGE";
  obs->timestamp = toTimestamp(t);
  obs->minSensorDistance = static_cast<float>(scan.min_range);
  obs->maxSensorDistance = static_cast<float>(scan.max_range);
  obs->fieldOfView_yaw = static_cast<float>(scan.fov_yaw);
  obs->fieldOfView_pitch = 0;
  obs->sensorLocationOnRobot = mrpt::poses::CPose3D(scan.sensor_pose_on_robot);
  obs->validCovariances = false;
  obs->sensor_std_range = static_cast<float>(scan.std_range);
  obs->sensor_std_yaw = static_cast<float>(scan.std_yaw);
  obs->sensor_std_pitch = 0;
  std::set<LandmarkId> seen;
  obs->sensedData.reserve(scan.readings.size());
  for (const auto& r : scan.readings) {
    if (r.id != kNoLandmarkId) {
      if (r.id < 0 || r.id > std::numeric_limits<int32_t>::max())
        throw InputError("landmark id " + std::to_string(r.id) + " does not fit MRPT's int32");
      if (!seen.insert(r.id).second)
        throw InputError("landmark id " + std::to_string(r.id) +
                         " appears twice in one observation");
    }
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = static_cast<float>(r.range);
    m.yaw = static_cast<float>(r.yaw);
    m.pitch = static_cast<float>(r.pitch);
    m.landmarkID =
        r.id == kNoLandmarkId ? mrpt::obs::INVALID_LANDMARK_ID : static_cast<int32_t>(r.id);
    obs->sensedData.push_back(m);
  }
  auto frame = mrpt::obs::CSensoryFrame::Create();
  frame->insert(obs);
  return frame;
}

Step makeStep(StepIndex index, double t, const std::optional<OdometryIncrement>& odometry,
              const std::optional<RangeBearingScan>& scan) {
  Step step;
  step.index = index;
  step.t = mrpt::Clock::toDouble(toTimestamp(t));
  if (odometry) {
    step.action = makeAction(*odometry, t);
    OdometryIncrement odo = *odometry;
    // The pose MRPT stores (CPose2D keeps phi wrapped to (-pi, pi]).
    const mrpt::poses::CPose2D stored(odo.mean.x, odo.mean.y, odo.mean.phi);
    odo.mean = toPose2(stored.asTPose());
    odo.cov = 0.5 * (odo.cov + odo.cov.transpose()).eval();
    step.odometry = odo;
  } else {
    step.action = mrpt::obs::CActionCollection::Create();
  }
  if (scan) {
    step.frame = makeFrame(*scan, t);
    // The parsed fields are copied back from the observation, so they hold exactly the (float)
    // values MRPT stores. (Rounding the doubles in place instead, (double)(float)x in a loop, is
    // miscompiled by GCC 12's SLP vectorizer at -O2: the round trip is folded away.)
    const auto obs = step.frame->getObservationByClass<mrpt::obs::CObservationBearingRange>();
    RangeBearingScan s;
    s.sensor_pose_on_robot = obs->sensorLocationOnRobot.asTPose();
    s.min_range = obs->minSensorDistance;
    s.max_range = obs->maxSensorDistance;
    s.fov_yaw = obs->fieldOfView_yaw;
    s.std_range = obs->sensor_std_range;
    s.std_yaw = obs->sensor_std_yaw;
    s.readings.reserve(obs->sensedData.size());
    for (std::size_t i = 0; i < obs->sensedData.size(); ++i) {
      const auto& m = obs->sensedData[i];
      s.readings.push_back({scan->readings[i].id, m.range, m.yaw, m.pitch});
    }
    step.scan = std::move(s);
  } else {
    step.frame = mrpt::obs::CSensoryFrame::Create();
  }
  return step;
}

}  // namespace budget_slam::dataset
