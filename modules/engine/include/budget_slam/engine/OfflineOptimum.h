#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/metrics/GroundTruthErrors.h"

namespace budget_slam::runs {

/// One final map of a comparison: its run and the ids it kept.
struct FinalMap {
  std::string run;
  std::vector<LandmarkId> kept;
};

/// `compare --offline-optimum` (docs/ALGORITHMS.md "place-coverage", "offline optimum"): the
/// places of `place-coverage` ([PlaceCoverageReducer] of `ini`) built from the unreduced
/// reference run, its online poses and each step's landmark IDs; the best coverage any `cap`
/// landmarks give with hindsight (reducers::solvePlaceCoverageOptimum); and the coverage of each
/// final map. Writes `csv_path` (`run,landmarks,coverage_places,pct_of_optimum`, the last row
/// "offline optimum") atomically and returns a Markdown table of the same rows.
/// Throws InputError when the readings carry no landmark IDs, or the problem exceeds the size
/// limit (one line naming the size).
std::string writeOfflineOptimum(const std::string& csv_path,
                                const mrpt::config::CConfigFileBase& ini,
                                const std::vector<Step>& steps,
                                const std::vector<metrics::PoseRecord>& reference_poses,
                                const std::vector<FinalMap>& maps, std::size_t cap);

}  // namespace budget_slam::runs
