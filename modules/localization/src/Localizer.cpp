#include "budget_slam/localization/Localizer.h"

#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/ekf/EkfSlamOptions.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::runs {
namespace {

constexpr double kDeg = M_PI / 180;

/// The reference pose at time t (timestamps as written by budget-slam: equal to the rawlog's).
const TrajectoryPoint* atTime(const std::vector<TrajectoryPoint>& ref, double t) {
  const double tol = 1e-6 * std::max(1.0, std::abs(t));
  const auto it = std::lower_bound(ref.begin(), ref.end(), t - tol,
                                   [](const TrajectoryPoint& p, double v) { return p.t < v; });
  return it != ref.end() && std::abs(it->t - t) <= tol ? &*it : nullptr;
}

const std::vector<std::string>& localizationStepsColumns() {
  static const std::vector<std::string> c = {"step",
                                             "t",
                                             "x",
                                             "y",
                                             "yaw",
                                             "var_x",
                                             "var_y",
                                             "var_yaw",
                                             "map_landmarks_seen",
                                             "readings_used",
                                             "readings_gated",
                                             "error_m",
                                             "lost",
                                             "step_ms",
                                             "recovered",
                                             "scored",
                                             "tracked"};
  return c;
}

}  // namespace

LocalizationInputs resolveLocalization(const std::vector<Step>& steps, std::size_t steps_in_rawlog,
                                       const dataset::GroundTruth& gt,
                                       const std::optional<metrics::MapAlignment>& alignment,
                                       const std::optional<Pose2>& given,
                                       const std::vector<TrajectoryPoint>* reference,
                                       const std::string& reference_file,
                                       const LocalizationOptions& options) {
  LocalizationInputs in;
  auto& truth = in.truth;
  truth.poses.assign(steps.size(), std::nullopt);
  std::optional<Pose2> start;
  if (!gt.path.empty() && alignment) {
    truth.kind = "ground_truth";
    truth.file = gt.path_file;
    const std::size_t rows = gt.path.size();
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const std::size_t row = metrics::groundTruthRow(steps[k].index, rows, steps_in_rawlog);
      if (row < rows) truth.poses[k] = alignment->apply(gt.path[row]);
    }
    for (const auto& [id, p] : gt.landmarks)
      truth.landmarks.push_back(alignment->transform.apply(p));
    // The pose before the first step: row 0 (MRPT's layout: the start pose first), or, with one
    // row a step, row 0 taken back by the first step's odometry.
    mrpt::poses::CPose2D s(toTPose2D(gt.path.front()));
    if (rows == steps_in_rawlog && !steps.empty() && steps.front().odometry)
      s = s + (-mrpt::poses::CPose2D(toTPose2D(steps.front().odometry->mean)));
    start = alignment->apply(toPose2(s.asTPose()));
  } else if (reference) {
    truth.kind = "reference_trajectory";
    truth.file = reference_file;
    for (std::size_t k = 0; k < steps.size(); ++k)
      if (const auto* p = atTime(*reference, steps[k].t)) truth.poses[k] = p->pose;
    if (!steps.empty()) {
      const double t0 = steps.front().t, tol = 1e-6 * std::max(1.0, std::abs(t0));
      const auto it = std::lower_bound(reference->begin(), reference->end(), t0 - tol,
                                       [](const TrajectoryPoint& p, double v) { return p.t < v; });
      if (it != reference->begin())
        start = std::prev(it)->pose;  // the last reference pose before the traversal
      else if (const auto* p = atTime(*reference, t0))
        start = p->pose;
    }
  }
  if (given) {
    in.start.mean = *given;
    in.start_source = "--start-pose";
  } else if (start) {
    in.start.mean = *start;
    in.start_source = truth.kind == "ground_truth" ? "ground truth" : "reference trajectory";
  } else if (truth.kind == "reference_trajectory") {
    throw InputError(reference_file + ": no pose at or before the traversal's first time (" +
                     std::to_string(steps.empty() ? 0.0 : steps.front().t) +
                     " s); give --start-pose x,y,yaw");
  } else {
    throw ConfigError(
        "no start pose: give --start-pose x,y,yaw, or a traversal with ground truth and a map "
        "made with ground truth, or --reference-trajectory");
  }
  const double sxy = options.start_std_xy, syaw = options.start_std_yaw_deg * kDeg;
  in.start.cov = Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal();
  const auto scan = std::find_if(steps.begin(), steps.end(), [](const Step& s) { return s.scan; });
  in.sensor_range = scan != steps.end() ? scan->scan->max_range : 0;
  in.places = PlaceGrid::fromSensor(options.place_size, options.heading_sectors, in.sensor_range,
                                    scan != steps.end() ? scan->scan->fov_yaw : 0);
  return in;
}

Localizer::Localizer(const mrpt::config::CConfigFileBase& ini, const LocalizationOptions& options,
                     std::size_t min_landmarks, report::OutputFolder folder,
                     const std::vector<LandmarkView>& map, const LocalizationInputs& inputs)
    : folder_(std::move(folder)),
      options_(options),
      inputs_(inputs),
      min_landmarks_(min_landmarks),
      steps_csv_(folder_.file("steps.csv"), localizationStepsColumns()),
      scorer_(options.lost_threshold, min_landmarks, options.success_xy,
              options.success_yaw_deg * kDeg),
      area_(inputs.mapping_path.empty()
                ? metrics::MappedArea()
                : metrics::MappedArea(inputs.mapping_path, inputs.places.size(),
                                      inputs.sensor_range)) {
  report::ReportOptions report_options;
  report_options.loadFromConfigFile(ini, report::ReportOptions::kSection);
  figure_formats_ = report_options.figure_formats;
  figure_title_ = report_options.figure_title;
  traversal_name_ = std::filesystem::path(ini.read_string("MappingApplication", "rawlog_file", ""))
                        .filename()
                        .string();
  kf_.loadOptions(ini);        // MRPT's own sections, as for mapping
  ekf::EkfSlamOptions update;  // and the mapping filter's Kalman update
  update.loadFromConfigFile(ini, ekf::EkfSlamOptions::kSection);
  kf_.setUpdate(update.update);
  kf_.KF_options.verbosity_level = mrpt::system::LVL_ERROR;
  kf_.gate = {options.gate_chi2, options.recover_after_steps, options.recovery_window_steps,
              options.recovery_min_landmarks};
  kf_.initialize(inputs.start, map);
  for (const auto& l : map) map_ids_.insert(l.id);
}

void Localizer::process(const Step& step) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t k = steps_done_;
  std::size_t seen = 0, used = 0, gated = 0, not_in_map = 0, consistent = 0;
  bool recovered = false;
  if (!diverged_at_) {
    try {
      kf_.processStep(step);
      const auto p = kf_.robotPose();
      if (!std::isfinite(p.mean.x) || !std::isfinite(p.mean.y) || !std::isfinite(p.mean.phi) ||
          !p.cov.allFinite())
        diverged_at_ = step.index, diverged_why_ = "the robot pose or its covariance is not finite";
    } catch (const std::exception& e) {
      const std::string what = e.what();
      diverged_at_ = step.index,
      diverged_why_ = "MRPT's filter failed: " + what.substr(0, what.find('\n'));
    }
  }
  if (!diverged_at_) {
    // Map landmarks observed: readings with a sensor ID the map holds; ID-less readings only
    // through the filter's pairing.
    std::set<LandmarkId> in_view;
    const auto& use = kf_.lastUsed();
    if (step.scan)
      for (std::size_t r = 0; r < step.scan->readings.size(); ++r) {
        const LandmarkId id = step.scan->readings[r].id;
        if (id != kNoLandmarkId && map_ids_.count(id)) in_view.insert(id);
        if (id == kNoLandmarkId && r < use.size() && use[r] != kNoLandmarkId)
          in_view.insert(use[r]);
        if (r < use.size() && use[r] != kNoLandmarkId) ++used;
        if (id != kNoLandmarkId && !map_ids_.count(id)) ++not_in_map;
      }
    seen = in_view.size();
    gated = kf_.lastGated();
    recovered = kf_.lastRecovered();
    consistent = kf_.lastConsistent();
  }

  const auto& truth = k < inputs_.truth.poses.size() ? inputs_.truth.poses[k] : std::nullopt;
  const PoseEstimate pose = diverged_at_ ? PoseEstimate() : kf_.robotPose();
  metrics::StepError e;
  e.map_landmarks = seen;
  if (truth) {
    const double inf = std::numeric_limits<double>::infinity();
    e.error_m = diverged_at_ ? inf : std::hypot(pose.mean.x - truth->x, pose.mean.y - truth->y);
    e.yaw_error =
        diverged_at_ ? inf : std::abs(std::remainder(pose.mean.phi - truth->phi, 2 * M_PI));
    if (!diverged_at_ && inputs_.truth.kind == "ground_truth")
      e.nees = metrics::poseNees(pose, *truth);
    e.in_mapped_area = area_.contains(truth->x, truth->y);
    e.place = inputs_.places.placeOf(*truth);
  }
  const double error = e.error_m;
  // The step counts once its row is written: a row that cannot be (a full disk) leaves the
  // step out of every count, so that steps.csv, trajectory.tum and summary.json agree.
  metrics::LocalizationScorer scored = scorer_;
  const bool lost = scored.add(e);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  steps_csv_.cell(step.index)
      .cell(step.t)
      .cell(diverged_at_ ? nan : pose.mean.x)
      .cell(diverged_at_ ? nan : pose.mean.y)
      .cell(diverged_at_ ? nan : pose.mean.phi)
      .cell(diverged_at_ ? nan : pose.cov(0, 0))
      .cell(diverged_at_ ? nan : pose.cov(1, 1))
      .cell(diverged_at_ ? nan : pose.cov(2, 2))
      .cell(seen)
      .cell(used)
      .cell(gated)
      .cell(error)
      .cell(truth ? (lost ? 1 : 0) : -1)
      .cell(1e3 * dt)
      .cell(recovered ? 1 : 0)
      .cell(truth ? (e.in_mapped_area ? 1 : 0) : -1)
      .cell(truth && e.in_mapped_area ? (scorer_.tracked(e.error_m, e.yaw_error) ? 1 : 0) : -1);
  steps_csv_.endRow();
  scorer_ = std::move(scored);
  ++steps_done_;
  used_ += used, gated_ += gated, not_in_map_ += not_in_map;
  recoveries_ += recovered, consistent_ += consistent;
  total_s_ += dt;
  if (truth) truth_rows_.push_back({step.index, step.t, *truth});
  if (!diverged_at_) {
    trajectory_.push_back({step.index, step.t, pose.mean});
    in_view_.push_back(seen);
  }
}

LocalizationOutcome Localizer::outcome() const {
  LocalizationOutcome o;
  o.start = {inputs_.start, inputs_.start_source};
  o.counts = {steps_done_, map_ids_.size()};
  auto& m = o.localization;
  m.min_landmarks = min_landmarks_;
  m.lost_threshold_m = options_.lost_threshold;
  m.error_against = inputs_.truth.kind;
  m.error_file = inputs_.truth.file;
  m.success_xy_m = options_.success_xy;
  m.success_yaw_deg = options_.success_yaw_deg;
  m.place_size_m = inputs_.places.size();
  m.heading_sectors = inputs_.places.sectors();
  m.mapped_everywhere = area_.everywhere();
  m.mapped_cell_m = area_.cell();
  m.mapped_reach_m = inputs_.sensor_range;
  m.score = scorer_.score();
  m.readings_used = used_;
  m.readings_gated = gated_;
  m.recoveries = recoveries_;
  m.readings_not_in_map = not_in_map_;
  m.readings_consistent_with_map = consistent_;
  m.diverged_at_step = diverged_at_;
  m.diverged_why = diverged_why_;
  o.timings.steps_s = total_s_;
  if (steps_done_) o.timings.step_ms_mean = 1e3 * total_s_ / steps_done_;
  return o;
}

runs::RunOutcome Localizer::finish(runs::RunStatus status, runs::ErrorKind kind,
                                   const std::string& error, const runs::RunGiven& given,
                                   const std::optional<LocalizationWakeUp>& wake_up) {
  // Every output is attempted (a full disk fails some); summary.json, last, says which were not.
  std::vector<std::string> not_written;
  const auto attempt = [&](const std::string& name, const std::function<void()>& write) {
    try {
      write();
    } catch (const std::exception& e) {
      not_written.push_back(name);
      if (write_error_.empty()) write_error_ = report::outputFailureLine(e);
    }
  };
  attempt("steps.csv", [&] { steps_csv_.close(); });
  const auto landmarks = kf_.landmarks();
  attempt("trajectory.tum",
          [&] { report::writeTrajectoryTum(folder_.file("trajectory.tum"), trajectory_); });
  attempt("landmarks.csv", [&] {
    report::writeLandmarksCsv(folder_.file("landmarks.csv"),
                              diverged_at_ ? std::vector<LandmarkView>() : landmarks);
  });
  const std::string truth_file =
      inputs_.truth.kind == "ground_truth" ? "ground_truth.tum" : "reference.tum";
  if (!inputs_.truth.kind.empty())
    attempt(truth_file, [&] { report::writeTrajectoryTum(folder_.file(truth_file), truth_rows_); });

  const auto s = scorer_.score();
  report::MapContent map;
  map.title =
      "localization in a map of " + std::to_string(map_ids_.size()) + " landmarks: " +
      (std::isfinite(s.lost_pct)
           ? std::to_string(static_cast<int>(std::lround(s.lost_pct))) + "% of the steps lost"
           : "no truth to compare with");
  for (const auto& p : trajectory_) map.trajectory.push_back(p.pose);
  map.trajectory_landmarks = in_view_;
  map.min_landmarks = min_landmarks_;
  if (!diverged_at_) map.kept = landmarks;
  for (const auto& p : truth_rows_) map.ground_truth_path.push_back(p.pose);
  map.ground_truth_landmarks = inputs_.truth.landmarks;
  if (!traversal_name_.empty()) map.title = traversal_name_ + ": " + map.title;
  if (!figure_title_) map.title.clear();
  for (const auto format : figure_formats_) {
    const std::string name = report::figureFile("map", format);
    attempt(name, [&] { report::writeMapFigure(folder_.file(name), map, format); });
  }

  runs::RunOutcome o;
  o.status = status, o.kind = kind, o.error = error;
  if (o.ok() && !write_error_.empty())
    o.fail(runs::RunStatus::Failed, runs::ErrorKind::Output, write_error_);
  o.files_not_written = not_written;
  o.localization = outcome();
  o.wake_up = wake_up;
  o.given.command = "localize";
  o.given.update(given);
  try {
    runs::writeSummary(folder_.file("summary.json"), o);
  } catch (const std::exception& e) {
    summary_error_ = failureLine(e);
  }
  return o;
}

}  // namespace budget_slam::runs
