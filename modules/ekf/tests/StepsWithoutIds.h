// A step as it would come from a rawlog whose readings carry no landmark ID, for the tests that
// run the EKF on MRPT's own data association.
#pragma once

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <memory>

#include "budget_slam/core/Step.h"

namespace budget_slam::testing {

/// A deep copy of `s` whose bearing-range readings (and scan) carry no landmark ID.
inline Step withoutIds(const Step& s) {
  Step out = s;
  if (!s.frame) return out;
  out.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  for (const auto& o : *s.frame) {
    if (auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o)) {
      auto c = std::make_shared<mrpt::obs::CObservationBearingRange>(*br);
      for (auto& m : c->sensedData) m.landmarkID = -1;
      out.frame->insert(c);
    } else {
      out.frame->insert(o);
    }
  }
  if (out.scan)
    for (auto& r : out.scan->readings) r.id = kNoLandmarkId;
  return out;
}

}  // namespace budget_slam::testing
