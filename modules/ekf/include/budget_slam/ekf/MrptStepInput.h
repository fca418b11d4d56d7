#pragma once
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include "budget_slam/core/Step.h"

namespace budget_slam::ekf {

/// What MRPT's CRangeBearingKFSLAM2D::processActionObservation is given for one step: the step's
/// own action (an empty one when it has none) and frame. MRPT's filter asserts a bearing-range
/// observation in every frame, so a frame without one gets an empty one added (no readings: the
/// step is a prediction only); the step's shared objects are never modified.
struct MrptStepInput {
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
};
MrptStepInput mrptStepInput(const Step& step);

}  // namespace budget_slam::ekf
