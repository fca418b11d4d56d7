#include "budget_slam/engine/RawlogSteps.h"

#include <set>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/dataset/RawlogReader.h"

namespace budget_slam::runs {

void requireBearingRange(const dataset::RawlogReader& reader, const std::string& rawlog) {
  if (reader.bearingRangeSteps() > 0) return;
  std::string held;
  for (const auto& n : reader.observationClasses()) held += (held.empty() ? "" : ", ") + n;
  throw InputError("rawlog '" + rawlog + "' holds no CObservationBearingRange (it holds: " +
                   (held.empty() ? std::string("none") : held) + ")");
}

std::optional<std::vector<Step>> readRawlogSteps(const std::string& rawlog, std::size_t limit,
                                                 ProgressReporter* reading) {
  std::vector<Step> steps;
  dataset::RawlogReader reader(rawlog);
  // A signal ends the reading within one read of the file, even inside a large object.
  reader.setStopCheck([] { return Cancellation::requested(); });
  while (limit == 0 || steps.size() < limit) {
    auto s = reader.next();
    if (s) {
      steps.push_back(std::move(*s));
      if (reading)
        reading->update(limit ? double(steps.size()) / double(limit) : reader.progress(),
                        steps.size(), limit, "");
    } else if (!reader.stopped()) {
      break;
    }
    if (Cancellation::requested()) {
      if (reading) reading->finish(false);
      return std::nullopt;
    }
  }
  if (reading) reading->finish(true);
  requireBearingRange(reader, rawlog);
  return steps;
}

}  // namespace budget_slam::runs
