#pragma once
#include <set>

#include "budget_slam/core/Step.h"

namespace budget_slam {

/// A copy of `step` whose parsed scan lacks the readings of the landmarks in `ids`. The rawlog's
/// MRPT objects (`action`, `frame`) stay shared and untouched: the parsed readings alone say
/// which readings count, and the EKF hands MRPT the rawlog's observation restricted to them
/// (ekf::mrptStepInput). Used to keep evicted landmarks out when [LandmarkBudget]
/// readmit_evicted = false. Returns the step unchanged when none of its readings is affected.
Step withoutReadingsOf(const Step& step, const std::set<LandmarkId>& ids);

}  // namespace budget_slam
