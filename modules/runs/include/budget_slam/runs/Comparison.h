#pragma once
// compare's work between its runs' steps and its table (docs/ARCHITECTURE.md "A compare"): the
// rawlog read once, the runs made, each run ended against the reference, comparison.csv's row of
// a run, the comparison figure, and how the comparison ends.
#include <mrpt/config/CConfigFileMemory.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/engine/CompareRuns.h"
#include "budget_slam/metrics/ReferenceMetrics.h"
#include "budget_slam/report/ComparisonTable.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/runs/CompareOutcome.h"

namespace budget_slam::runs {

/// The unreduced run every comparison holds (its folder's name, comparison.csv's run).
inline constexpr const char* kReferenceRun = "reference";

/// A comparison's runs, the reference first.
using CompareRuns = std::vector<std::unique_ptr<CompareRun>>;

/// The reference run (reducer none) and one run a reducer of `names` (with `seeds`: one a reducer
/// and seed, named <reducer>/seed<S>), each with its folder under `top` and its config_used.ini,
/// appended to `runs` one by one (on an error, the runs made so far are there to say why in their
/// summary.json). `base` is every run's driver specification but its reducer and seed. The
/// reference drops nothing, so no seed changes it: it runs once.
void makeRuns(const mrpt::config::CConfigFileMemory& merged, const BackendRegistry& backends,
              const DriverSpec& base, const std::vector<std::string>& names,
              const std::vector<std::uint64_t>& seeds, const report::OutputFolder& top, bool force,
              const std::shared_ptr<dataset::GroundTruth>& truth, CompareRuns& runs);

/// Ends run `r`: its metrics against the reference (when both are ok) and its outputs
/// (RunDriver::finish, with `given` and the metrics in summary.json). A run whose outputs could not
/// be written, or whose estimate is not finite, becomes failed.
metrics::ReferenceMetrics finishRun(CompareRun& r, const CompareRun& ref, std::size_t steps,
                                    std::size_t eig_max_rows, RunGiven given);

/// comparison.csv's row of run `r` (docs/OUTPUTS.md), with `m` its metrics against the
/// reference, which holds `ref_landmarks` landmarks and `ref_poses` poses.
report::ComparisonRow comparisonRow(const CompareRun& r, const metrics::ReferenceMetrics& m,
                                    std::size_t ref_landmarks, std::size_t ref_poses);

/// comparison.<png|pdf|svg>: the landmark count over the steps (the cap marked), and the robot
/// position error against ground truth (else the difference to the reference run); the
/// reference dashed black.
void writeComparisonChart(const report::OutputFolder& top, const std::string& title,
                          const CompareRuns& runs, const std::vector<Step>& steps,
                          const dataset::GroundTruth* truth, std::optional<std::size_t> cap,
                          const std::vector<report::FigureFormat>& formats);

}  // namespace budget_slam::runs
