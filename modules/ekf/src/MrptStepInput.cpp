#include "budget_slam/ekf/MrptStepInput.h"

#include <mrpt/obs/CObservationBearingRange.h>

namespace budget_slam::ekf {

MrptStepInput mrptStepInput(const Step& step) {
  MrptStepInput in;
  in.action = step.action ? step.action : std::make_shared<mrpt::obs::CActionCollection>();
  in.frame = step.frame;
  if (!in.frame || !in.frame->getObservationByClass<mrpt::obs::CObservationBearingRange>()) {
    in.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
    if (step.frame)
      for (const auto& o : *step.frame) in.frame->insert(o);
    in.frame->insert(std::make_shared<mrpt::obs::CObservationBearingRange>());
  }
  return in;
}

}  // namespace budget_slam::ekf
