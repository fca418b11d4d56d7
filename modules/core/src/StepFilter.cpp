#include "budget_slam/core/StepFilter.h"

#include <mrpt/obs/CObservationBearingRange.h>

#include <algorithm>

namespace budget_slam {

Step withoutReadingsOf(const Step& step, const std::set<LandmarkId>& ids) {
  if (!step.scan || ids.empty()) return step;
  const auto& rs = step.scan->readings;
  const auto hit = [&](LandmarkId id) { return id != kNoLandmarkId && ids.count(id) > 0; };
  if (std::none_of(rs.begin(), rs.end(), [&](const auto& r) { return hit(r.id); })) return step;

  Step out = step;
  out.scan->readings.clear();
  for (const auto& r : rs)
    if (!hit(r.id)) out.scan->readings.push_back(r);

  if (step.frame) {
    auto frame = std::make_shared<mrpt::obs::CSensoryFrame>();
    bool replaced = false;
    for (const auto& obs : *step.frame) {
      auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(obs);
      if (br && !replaced) {
        // The first bearing-range observation is the one MRPT's filter and parseStep use.
        auto copy = std::make_shared<mrpt::obs::CObservationBearingRange>(*br);
        copy->sensedData.clear();
        for (const auto& m : br->sensedData)
          if (!hit(m.landmarkID < 0 ? kNoLandmarkId : LandmarkId(m.landmarkID)))
            copy->sensedData.push_back(m);
        frame->insert(copy);
        replaced = true;
      } else {
        frame->insert(obs);
      }
    }
    out.frame = frame;
  }
  return out;
}

}  // namespace budget_slam
