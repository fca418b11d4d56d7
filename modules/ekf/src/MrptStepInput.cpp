#include "budget_slam/ekf/MrptStepInput.h"

#include <mrpt/obs/CObservationBearingRange.h>

#include <stdexcept>
#include <string>

namespace budget_slam::ekf {
namespace {

using mrpt::obs::CObservationBearingRange;

bool sameReading(const CObservationBearingRange::TMeasurement& m, const RangeBearingReading& r) {
  const LandmarkId id = m.landmarkID < 0 ? kNoLandmarkId : LandmarkId(m.landmarkID);
  return id == r.id && m.range == r.range && m.yaw == r.yaw && m.pitch == r.pitch;
}

/// A copy of `obs` holding only the measurements `scan` kept, in their order (`scan`'s readings
/// are a subsequence of the observation's: they were parsed from it, then some were left out).
CObservationBearingRange::Ptr restrictedTo(const CObservationBearingRange& obs,
                                           const RangeBearingScan& scan, StepIndex step) {
  auto copy = std::make_shared<CObservationBearingRange>(obs);
  copy->sensedData.clear();
  std::size_t next = 0;
  for (const auto& m : obs.sensedData)
    if (next < scan.readings.size() && sameReading(m, scan.readings[next])) {
      copy->sensedData.push_back(m);
      ++next;
    }
  if (next != scan.readings.size())
    throw std::logic_error("step " + std::to_string(step) +
                           ": the parsed readings are not those of the rawlog's observation");
  return copy;
}

}  // namespace

MrptStepInput mrptStepInput(const Step& step) {
  MrptStepInput in;
  in.action = step.action ? step.action : std::make_shared<mrpt::obs::CActionCollection>();
  in.frame = step.frame;
  const auto obs =
      step.frame ? step.frame->getObservationByClass<CObservationBearingRange>() : nullptr;
  if (!obs) {
    in.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
    if (step.frame)
      for (const auto& o : *step.frame) in.frame->insert(o);
    in.frame->insert(std::make_shared<CObservationBearingRange>());
  } else if (step.scan && step.scan->readings.size() != obs->sensedData.size()) {
    // Readings left out of the parsed scan (core/StepFilter.h): MRPT gets the rawlog's
    // observation without them, the frame's other observations as they are.
    in.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
    for (const auto& o : *step.frame)
      in.frame->insert(o == obs ? restrictedTo(*obs, *step.scan, step.index) : o);
  }
  return in;
}

}  // namespace budget_slam::ekf
