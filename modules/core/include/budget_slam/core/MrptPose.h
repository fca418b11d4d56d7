#pragma once
// The pose type at MRPT's boundary: where an MRPT call or a core interface still holds an
// mrpt::math::TPose2D, the pose is converted here and nowhere else.
#include <mrpt/math/TPose2D.h>

#include "budget_slam/core/Pose2.h"

namespace budget_slam {

inline Pose2 toPose2(const mrpt::math::TPose2D& p) { return Pose2(p.x, p.y, p.phi); }
inline mrpt::math::TPose2D toTPose2D(const Pose2& p) {
  return mrpt::math::TPose2D(p.x, p.y, p.phi);
}

}  // namespace budget_slam
