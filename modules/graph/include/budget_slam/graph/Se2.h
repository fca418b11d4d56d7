#pragma once
// The SE(2) helpers live in core (budget_slam/core/Se2.h), shared with the wake-up on a saved map
// (modules/wakeup); the graph keeps its names for them.
#include "budget_slam/core/Se2.h"

namespace budget_slam::graph {

using budget_slam::between;
using budget_slam::compose;
using budget_slam::Pose2;
using budget_slam::rot2;
using budget_slam::wrapAngle;

}  // namespace budget_slam::graph
