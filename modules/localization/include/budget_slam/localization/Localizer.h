#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/ekf/LocalizationKF2D.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/metrics/LocalizationScore.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/metrics/MappedArea.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/ReportOptions.h"

namespace budget_slam::runs {

/// What a localization's position error is measured against, in the map's frame, one pose a
/// step of the traversal (nullopt: nothing for that step).
struct LocalizationTruth {
  std::string kind;  ///< "ground_truth", "reference_trajectory", or "" (none: no errors)
  std::string file;  ///< where it came from
  std::vector<std::optional<Pose2>> poses;
  std::vector<Eigen::Vector2d> landmarks;  ///< true landmarks in the map's frame (map.png)
};

/// The start pose and the truth of a localization, resolved from the map and the traversal.
struct LocalizationInputs {
  PoseEstimate start;
  std::string start_source;  ///< "--start-pose", "ground truth", "reference trajectory"
  LocalizationTruth truth;
  /// The places of the success per place and of the mapped area: from [Localization] place_size
  /// and heading_sectors and the traversal's sensor (its first scan).
  PlaceGrid places{1.0, 1};
  double sensor_range = 0;  ///< the traversal's sensor's maximum range [m], 0 when unknown
  /// The path of the run that made the map, in the map's frame: steps whose truth lies away from
  /// it are not scored (metrics::MappedArea). Empty: every step is scored.
  std::vector<Pose2> mapping_path;
};

/// Resolves the start pose and the truth (docs/OUTPUTS.md, "budget-slam localize"):
///  - truth: the traversal's ground-truth path brought into the map's frame by the mapping run's
///    `alignment`; without ground truth (or without an alignment), the `reference` trajectory
///    (poses matched by timestamp); else none;
///  - start: `given` when set, else the truth's pose before the first step (ground truth: the
///    path's start row; reference: its last pose before the first step's time);
///  - places: from `options` and the first scan of `steps` (mapping_path is left to the caller).
/// Throws InputError when there is no start pose, naming what to give.
/// `steps_in_rawlog` maps ground-truth rows (the traversal may be localized only in part).
LocalizationInputs resolveLocalization(const std::vector<Step>& steps, std::size_t steps_in_rawlog,
                                       const dataset::GroundTruth& traversal_truth,
                                       const std::optional<metrics::MapAlignment>& alignment,
                                       const std::optional<Pose2>& given,
                                       const std::vector<TrajectoryPoint>* reference,
                                       const std::string& reference_file,
                                       const LocalizationOptions& options);

/// One localization of a traversal in a fixed map (budget-slam localize): MRPT's EKF through
/// ekf::LocalizationKF2D, the outputs of `run` in its folder (trajectory.tum, steps.csv,
/// landmarks.csv, map.png, summary.json, ground_truth.tum or reference.tum), and the score.
class Localizer {
 public:
  Localizer(const mrpt::config::CConfigFileBase& ini, const LocalizationOptions& options,
            std::size_t min_landmarks, report::OutputFolder folder,
            const std::vector<LandmarkView>& map, const LocalizationInputs& inputs);

  /// One step. A filter that stops being finite (or that MRPT rejects) is not an error: the robot
  /// is lost from that step on (summary.json: diverged_at_step).
  void process(const Step& step);

  /// Writes trajectory.tum, landmarks.csv, map.png, the truth's .tum and summary.json
  /// (runs::writeSummary; `given` merged in). Each is attempted even when another fails (a full
  /// disk): the first failure is writeError() (and, for an ok localization, the outcome's error),
  /// one of summary.json itself summaryError(). Returns the outcome summary.json was written from:
  /// its localization blocks (RunOutcome::localization), `wake_up`, and `given` with command
  /// "localize".
  runs::RunOutcome finish(runs::RunStatus status, runs::ErrorKind kind, const std::string& error,
                          const runs::RunGiven& given = {},
                          const std::optional<LocalizationWakeUp>& wake_up = std::nullopt);
  /// The blocks finish() writes, as they stand.
  LocalizationOutcome outcome() const;
  /// The first output finish() could not write, "" when none.
  const std::string& writeError() const { return write_error_; }
  /// Why summary.json could not be written, "" when it was.
  const std::string& summaryError() const { return summary_error_; }

  metrics::LocalizationScore score() const { return scorer_.score(); }
  std::size_t stepsDone() const { return steps_done_; }
  /// Readings so far that agree with the map (ekf::LocalizationKF2D::lastConsistent).
  std::size_t readingsConsistentWithMap() const { return consistent_; }
  /// Readings so far paired with a landmark of the map (by sensor ID or association), gated or not.
  std::size_t readingsPairedWithMap() const { return used_ + gated_; }

 private:
  report::OutputFolder folder_;
  LocalizationOptions options_;
  LocalizationInputs inputs_;
  std::size_t min_landmarks_;
  ekf::LocalizationKF2D kf_;
  std::set<LandmarkId> map_ids_;
  std::vector<report::FigureFormat> figure_formats_;  ///< [Report] figure_format
  bool figure_title_ = true;                          ///< [Report] figure_title
  std::string traversal_name_;                        ///< the rawlog's file name, for the title
  report::CsvWriter steps_csv_;
  metrics::LocalizationScorer scorer_;
  metrics::MappedArea area_;
  std::vector<TrajectoryPoint> trajectory_, truth_rows_;
  std::vector<std::size_t> in_view_;  ///< map landmarks observed, one per trajectory pose
  std::optional<StepIndex> diverged_at_;
  std::string diverged_why_;
  std::string write_error_, summary_error_;
  std::size_t steps_done_ = 0, used_ = 0, gated_ = 0, not_in_map_ = 0, recoveries_ = 0,
              consistent_ = 0;
  double total_s_ = 0;
};

}  // namespace budget_slam::runs
