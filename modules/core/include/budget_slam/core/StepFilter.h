#pragma once
#include <set>

#include "budget_slam/core/Step.h"

namespace budget_slam {

/// A copy of `step` without the readings of the landmarks in `ids`: both the parsed scan and the
/// MRPT frame (a new CObservationBearingRange; the shared original is never touched). Used to
/// keep evicted landmarks out when [LandmarkBudget] readmit_evicted = false. Returns the step
/// unchanged (sharing its objects) when none of its readings is affected.
Step withoutReadingsOf(const Step& step, const std::set<LandmarkId>& ids);

}  // namespace budget_slam
