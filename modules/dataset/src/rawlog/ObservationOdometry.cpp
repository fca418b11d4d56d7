#include "ObservationOdometry.h"

#include <mrpt/obs/CActionRobotMovement2D.h>

namespace budget_slam::dataset::rawlog {

void ObservationOdometry::reading(const mrpt::obs::CObservationOdometry& odo) {
  if (!used_) {
    used_ = odo.odometry;  // the reference: the robot starts here
    return;
  }
  latest_ = odo.odometry;
  latest_t_ = odo.timestamp;
}

mrpt::obs::CActionCollection::Ptr ObservationOdometry::actionForStep() {
  auto action = mrpt::obs::CActionCollection::Create();
  if (!latest_) return action;
  mrpt::obs::CActionRobotMovement2D move;
  move.computeFromOdometry(*latest_ - *used_,
                           mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
  move.timestamp = latest_t_;
  action->insert(move);
  used_ = latest_;
  latest_.reset();
  return action;
}

}  // namespace budget_slam::dataset::rawlog
