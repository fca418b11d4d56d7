#pragma once
#include <mrpt/config/CConfigFileMemory.h>

#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/metrics/LocalizationScore.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/report/ComparisonTable.h"

namespace budget_slam::runs {

/// A traversal of `compare --relocalize`, read once: its rawlog, settings (its own sidecar
/// applied), steps and ground truth.
struct Traversal {
  std::string name;    ///< the rawlog's stem: the folder name under <run>/relocalize/
  std::string rawlog;  ///< resolved path
  mrpt::config::CConfigFileMemory ini;  ///< its merged configuration
  std::string config_used;              ///< config_used.ini's text for `ini`
  LocalizationOptions localization;     ///< [Localization] of `ini`
  std::vector<Step> steps;
  std::size_t steps_in_rawlog = 0;
  dataset::GroundTruth truth;
};

/// A run's final map as compare hands it to the localizations.
struct MapOfRun {
  std::string run;     ///< reference or the reducer's name
  std::string folder;  ///< the run's output folder
  std::vector<LandmarkView> landmarks;
  std::optional<metrics::MapAlignment> alignment;
  /// The mapping path in the map's frame: where relocalization is scored (metrics::MappedArea).
  std::vector<Pose2> mapping_path;
};

/// One localization of one traversal in one run's map.
struct RelocalizationResult {
  std::string run, traversal;
  runs::RunStatus status = runs::RunStatus::Ok;
  runs::ErrorKind kind = runs::ErrorKind::None;
  std::string error;
  metrics::LocalizationScore score;
};

/// Every map localizes every traversal, `threads` at a time; each writes the outputs of
/// `budget-slam localize` into <run folder>/relocalize/<traversal>/. A traversal without ground
/// truth is measured against `reference` (a trajectory.tum) when given. Never throws for one
/// localization: its result says failed and why. `progress`, when given, hears the steps done
/// over every localization.
std::vector<RelocalizationResult> relocalizeAll(const std::vector<MapOfRun>& maps,
                                                const std::vector<Traversal>& traversals,
                                                const std::vector<TrajectoryPoint>* reference,
                                                const std::string& reference_file, unsigned threads,
                                                bool force, ProgressReporter* progress = nullptr);

/// relocalization.csv: run, traversal, status, rmse_m, max_m, lost_pct, coverage_pct, nees_mean,
/// success_pct, scored_pct.
void writeRelocalizationCsv(const std::string& path,
                            const std::vector<RelocalizationResult>& results);

/// Fills the reloc_* columns of `rows` (matched by run name): means over the traversals, and the
/// ratios to the row of run `reference_run`.
void addRelocalizationColumns(std::vector<report::ComparisonRow>& rows,
                              const std::vector<RelocalizationResult>& results,
                              const std::string& reference_run);

}  // namespace budget_slam::runs
