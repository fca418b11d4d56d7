#pragma once
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"

namespace budget_slam::report {

/// trajectory.tum: `t x y z qx qy qz qw` a pose, z = 0, rotation about z only; readable by evo and
/// rpg_trajectory_evaluation (8 numeric columns, strictly increasing t, unit quaternions).
/// Written atomically (FileWrite.h); a non-finite pose is an Error, never written.
void writeTrajectoryTum(const std::string& path, const std::vector<TrajectoryPoint>& trajectory);

/// When a landmark was last confirmed and the passes through its view it has missed since
/// (the budget's negative evidence, reducers/NegativeEvidence.h).
struct LandmarkConfirmation {
  StepIndex last_confirmed_step = 0;
  std::size_t misses = 0;
};

/// landmarks.csv: id, x, y, cov_xx, cov_xy, cov_yy, n_obs, obs_mean_x, obs_mean_y, first_step,
/// last_step, last_confirmed_step, misses — one row a landmark in the final map. `confirmations`
/// holds one entry a landmark, in the same order; empty: last_step and 0 for every landmark.
/// Written atomically; a landmark with a non-finite mean or covariance is an Error.
void writeLandmarksCsv(const std::string& path, const std::vector<LandmarkView>& landmarks,
                       const std::vector<LandmarkConfirmation>& confirmations = {});

/// summary.json, pretty-printed, written atomically (temporary file, fsync, rename) so that a
/// reader never sees half a file; bytes of strings that are not UTF-8 are written as U+FFFD, so
/// the file is valid JSON whatever an error text echoes.
void writeJson(const std::string& path, const nlohmann::json& j);

/// summary.json of a run, compare or localization (writeJson). When the whole summary cannot be
/// written (a full disk), a short one that fits the space the output folder set aside for it:
/// status, error, started, files_not_written, earlier_run_moved_to, and `summary_cut` saying why
/// the rest is missing. Throws Error naming the file when not even that can be written.
void writeSummaryJson(const std::string& path, const nlohmann::json& summary);

/// The one line for an exception out of writing an output: core's failureLine() (an allocation
/// failure says "out of memory (...)").
std::string outputFailureLine(const std::exception& e);

/// Columns of steps.csv and evictions.csv (docs/OUTPUTS.md).
const std::vector<std::string>& stepsCsvColumns();
const std::vector<std::string>& evictionsCsvColumns();

}  // namespace budget_slam::report
