#pragma once
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include "budget_slam/core/Step.h"

namespace budget_slam::ekf {

/// What MRPT's CRangeBearingKFSLAM2D::processActionObservation is given for one step: the step's
/// own action (an empty one when it has none) and frame. MRPT's filter asserts a bearing-range
/// observation in every frame, so a frame without one gets an empty one added (no readings: the
/// step is a prediction only). When the step's parsed scan holds fewer readings than that
/// observation (readings left out by core/StepFilter.h), MRPT gets a copy of the observation
/// restricted to the readings kept, in their order. The step's shared objects are never
/// modified. Throws std::logic_error when the scan's readings are not a subsequence of the
/// observation's (a step not parsed from its frame).
struct MrptStepInput {
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
};
MrptStepInput mrptStepInput(const Step& step);

}  // namespace budget_slam::ekf
