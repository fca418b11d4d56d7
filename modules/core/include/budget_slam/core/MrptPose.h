#pragma once
// The pose type at MRPT's boundary: every interface of the project holds a Pose2; where an MRPT
// call takes or gives an mrpt::math::TPose2D (rawlog objects, the EKF glue, scenes, CPose2D
// arithmetic kept for its exact numbers; docs/ARCHITECTURE.md "The pose type"), the pose is
// converted here and nowhere else.
#include <mrpt/math/TPose2D.h>

#include "budget_slam/core/Pose2.h"

namespace budget_slam {

inline Pose2 toPose2(const mrpt::math::TPose2D& p) { return Pose2(p.x, p.y, p.phi); }
inline mrpt::math::TPose2D toTPose2D(const Pose2& p) {
  return mrpt::math::TPose2D(p.x, p.y, p.phi);
}

}  // namespace budget_slam
