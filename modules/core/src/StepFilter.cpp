#include "budget_slam/core/StepFilter.h"

#include <algorithm>

namespace budget_slam {

Step withoutReadingsOf(const Step& step, const std::set<LandmarkId>& ids) {
  if (!step.scan || ids.empty()) return step;
  const auto& rs = step.scan->readings;
  const auto hit = [&](LandmarkId id) { return id != kNoLandmarkId && ids.count(id) > 0; };
  if (std::none_of(rs.begin(), rs.end(), [&](const auto& r) { return hit(r.id); })) return step;

  // Only the parsed readings change: the rawlog's objects stay shared and untouched, and the EKF
  // restricts MRPT's observation to the readings kept (ekf/MrptStepInput.h).
  Step out = step;
  out.scan->readings.clear();
  for (const auto& r : rs)
    if (!hit(r.id)) out.scan->readings.push_back(r);
  return out;
}

}  // namespace budget_slam
