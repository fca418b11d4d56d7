#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Reducer.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::report {

/// One row of steps.csv (docs/OUTPUTS.md): the state after the step, SI units.
struct StepRow {
  StepIndex step = 0;
  double t = 0;               ///< [s]
  std::size_t landmarks = 0;  ///< in the map after the step's drops
  std::size_t added = 0;      ///< landmarks the step brought in
  std::size_t dropped = 0;    ///< landmarks dropped after holding a place (evictions.csv rows)
  std::size_t refused = 0;    ///< newcomers refused (evictions.csv rows with reason refused)
  std::size_t poses = 0;      ///< poses the backend holds
  PoseEstimate pose;          ///< online robot pose and its covariance
  double step_ms = 0;         ///< wall time of the step [ms]
  double cpu_ms = 0;          ///< CPU time of the step's thread [ms]
  std::size_t rss_bytes = 0;  ///< resident memory after the step [bytes]
  std::size_t reloc_landmarks = 0;       ///< landmarks of the map held then, observed then
  double reloc_coverage_so_far_pct = 0;  ///< [%]
};

/// One row of evictions.csv (docs/OUTPUTS.md): a landmark dropped, or a newcomer refused.
struct EvictionRow {
  StepIndex step = 0;
  LandmarkId id = kNoLandmarkId;
  std::string reducer;
  double score = 0;  ///< the reducer's score of the landmark (lower = less useful)
  std::size_t n_before = 0, n_after = 0;
  std::string reason;  ///< over_cap, over_cap_all_protected, refused, objective, incremental
  /// What each shadow reducer would have dropped (id kNoLandmarkId: it failed here).
  std::vector<std::pair<std::string, ReducerChoice>> shadow;
  std::vector<std::pair<std::string, std::string>> shadow_errors;  ///< shadow name, why
};

/// The files of a finished run besides summary.json, and what they are made of (only the steps
/// that completed and only finite estimates).
struct RunEndFiles {
  std::vector<TrajectoryPoint> trajectory;
  std::vector<LandmarkView> landmarks;
  /// landmarks.csv's last two columns, one a landmark (writeLandmarksCsv); empty: from last_step.
  std::vector<LandmarkConfirmation> confirmations;
  /// What the map figure and map.3Dscene show; called at most once (the k-means it runs is not
  /// cheap).
  std::function<MapContent()> map;
  std::vector<FigureFormat> figure_formats = {FigureFormat::Png};  ///< map.png, map.pdf, ...
  bool scene = true;                                               ///< write map.3Dscene
  Pose2 robot;                                  ///< where map.3Dscene draws the robot
  const dataset::GroundTruth* truth = nullptr;  ///< ground_truth.tum when it has a path
  std::size_t steps_in_rawlog = 0;              ///< maps ground-truth rows (groundTruthRow)
};

/// The files one run writes in its folder (docs/OUTPUTS.md): steps.csv and evictions.csv a row at
/// a time as the run goes, state dumps and kf-slam's per-step scenes during the run, then at the
/// end trajectory.tum, landmarks.csv, map.<png|pdf|svg>, map.3Dscene, ground_truth.tum and, last,
/// summary.json. Every write is checked (Error naming the file).
class RunOutputs {
 public:
  /// Opens steps.csv and evictions.csv (headers written) in `folder`.
  explicit RunOutputs(OutputFolder folder);

  const OutputFolder& folder() const { return folder_; }

  /// Appends a row; throws Error when it cannot be written.
  void addStep(const StepRow& row);
  void addEviction(const EvictionRow& row);

  /// states/step_<step>.txt: the backend's full mean and covariance, robot pose first then the
  /// landmarks in the backend's order, so that any reducer's score can be recomputed by hand.
  void writeState(const Backend& backend, StepIndex step) const;

  /// `name` (map.3Dscene, or kf_state_<step>.3Dscene during the run): MRPT's SceneViewer3D file.
  void writeScene(const std::string& name, const MapContent& map, const Pose2& robot) const;

  /// The end files, in this order: steps.csv and evictions.csv flushed, trajectory.tum,
  /// landmarks.csv, the map figures, map.3Dscene, ground_truth.tum. Each is attempted even when
  /// another fails (a full disk); returns the names of those not written, and the first error.
  struct EndFilesResult {
    std::vector<std::string> not_written;
    std::string first_error;  ///< "" when all were written
  };
  EndFilesResult writeEndFiles(const RunEndFiles& files);
  /// A run that did no step has no result: its steps.csv and evictions.csv, which hold only
  /// their headers, are removed, and no end file is written (summary.json says why).
  void discardStepFiles();

 private:
  OutputFolder folder_;
  CsvWriter steps_csv_, evictions_csv_;
};

/// ground_truth.tum: the ground truth of every pose of `trajectory`, same timestamps, in the
/// estimate's frame (`evo_ape tum ground_truth.tum trajectory.tum` compares them).
void writeGroundTruthTum(const std::string& path, const std::vector<TrajectoryPoint>& trajectory,
                         const dataset::GroundTruth& truth, std::size_t steps_in_rawlog);

}  // namespace budget_slam::report
