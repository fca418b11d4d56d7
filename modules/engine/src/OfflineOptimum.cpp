#include "budget_slam/engine/OfflineOptimum.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/reducers/PlaceCoverageOptimum.h"
#include "budget_slam/reducers/PlaceCoverageReducer.h"

namespace budget_slam::runs {

std::string writeOfflineOptimum(const std::string& csv_path,
                                const mrpt::config::CConfigFileBase& ini,
                                const std::vector<Step>& steps,
                                const std::vector<metrics::PoseRecord>& reference_poses,
                                const std::vector<FinalMap>& maps, std::size_t cap) {
  reducers::PlaceCoverageOptions options;
  options.loadFromConfigFile(ini, reducers::PlaceCoverageOptions::kSection);
  // Every place of the run is kept: the bound is over the whole run, not a bounded memory.
  options.max_places = steps.size() + 1;
  reducers::PlaceCoverageReducer places(options);
  for (std::size_t k = 0; k < steps.size() && k < reference_poses.size(); ++k) {
    if (!steps[k].scan) continue;
    StepObservation seen;
    seen.step = steps[k].index;
    seen.robot = reference_poses[k].estimate.mean;
    seen.sensor_max_range = steps[k].scan->max_range;
    seen.sensor_fov = steps[k].scan->fov_yaw;
    for (const auto& r : steps[k].scan->readings) {
      if (r.id == kNoLandmarkId)
        throw InputError("--offline-optimum: step " + std::to_string(steps[k].index) +
                         " has a reading without a landmark ID; the optimum needs IDs");
      seen.observed.push_back(r.id);
    }
    places.observe(seen);
  }
  const auto sightings = places.placeSightings();
  reducers::PlaceCoverageOptimum best;
  try {
    best = reducers::solvePlaceCoverageOptimum(sightings, options.min_landmarks, cap);
  } catch (const std::length_error& e) {
    throw InputError(std::string("--offline-optimum: ") + e.what());
  }

  const auto coverageOf = [&](std::vector<LandmarkId> ids) {
    std::sort(ids.begin(), ids.end());
    double f = 0;
    for (const auto& p : sightings) {
      std::size_t n = 0;
      for (const LandmarkId id : p) n += std::binary_search(ids.begin(), ids.end(), id);
      f += static_cast<double>(std::min(n, options.min_landmarks));
    }
    return f;
  };
  struct Row {
    std::string run;
    std::size_t landmarks;
    double coverage;
  };
  std::vector<Row> rows;
  for (const auto& m : maps) rows.push_back({m.run, m.kept.size(), coverageOf(m.kept)});
  rows.push_back({best.proven_optimal ? "offline optimum" : "offline optimum (time limit)",
                  best.selection.size(), best.coverage});

  const auto pct = [&](double f) {
    return best.coverage > 0 ? 100.0 * f / best.coverage : std::nan("");
  };
  std::ostringstream csv, md;
  csv << "run,landmarks,coverage_places,pct_of_optimum\n" << std::setprecision(10);
  md << "\nPlace coverage of the final maps (" << sightings.size() << " places of the reference "
     << "run, k = " << options.min_landmarks << ") against the best " << cap
     << " landmarks with hindsight:\n\n| run | landmarks | coverage [places] | % of optimum |\n"
     << "|---|---|---|---|\n"
     << std::fixed << std::setprecision(1);
  for (const auto& r : rows) {
    csv << r.run << "," << r.landmarks << "," << r.coverage << "," << pct(r.coverage) << "\n";
    md << "| " << r.run << " | " << r.landmarks << " | " << r.coverage << " | " << pct(r.coverage)
       << " |\n";
  }
  writeFileAtomically(csv_path, csv.str());  // checked, whole or not at all
  return md.str();
}

}  // namespace budget_slam::runs
