#pragma once
// A rawlog read whole, as compare, localize and --relocalize read it (a run reads it step by step
// instead), and the one check that it holds what budget-slam maps from.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Step.h"

namespace budget_slam {
class ProgressReporter;
namespace dataset {
class RawlogReader;
}
}  // namespace budget_slam

namespace budget_slam::runs {

/// Throws InputError "rawlog '<rawlog>' holds no CObservationBearingRange (it holds: ...)" when
/// none of the steps `reader` read held a bearing-range reading.
void requireBearingRange(const dataset::RawlogReader& reader, const std::string& rawlog);

/// The rawlog's steps, at most `limit` (0 = all), with their progress on `reading` (none: no
/// progress); nullopt when a stop request (core/Cancellation.h) came while reading. Throws as
/// dataset::RawlogReader does, and as requireBearingRange.
std::optional<std::vector<Step>> readRawlogSteps(const std::string& rawlog, std::size_t limit,
                                                 ProgressReporter* reading);

}  // namespace budget_slam::runs
