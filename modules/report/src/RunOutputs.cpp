#include "budget_slam/report/RunOutputs.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/report/MapScene.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::report {
namespace {

/// A cell of evictions.csv's shadow_choices: `name:id:score` a shadow, `;`-separated; a shadow
/// that failed at this drop has empty id and score (`name::`).
std::string shadowChoices(const EvictionRow& e) {
  std::string out;
  for (const auto& [name, choice] : e.shadow) {
    out += (out.empty() ? "" : ";") + name + ":";
    if (choice.id != kNoLandmarkId)
      out += std::to_string(choice.id) + ":" +
             (std::isnan(choice.score) ? std::string() : formatDouble(choice.score));
    else
      out += ":";
  }
  return out;
}

/// A cell of evictions.csv's shadow_errors: `name: why` a failed shadow, `;`-separated (a `;`
/// inside a message reads as `,`).
std::string shadowErrors(const EvictionRow& e) {
  std::string out;
  for (auto [name, why] : e.shadow_errors) {
    std::replace(why.begin(), why.end(), ';', ',');
    out += (out.empty() ? "" : ";") + name + ": " + why;
  }
  return out;
}

}  // namespace

RunOutputs::RunOutputs(OutputFolder folder)
    : folder_(std::move(folder)),
      steps_csv_(folder_.file("steps.csv"), stepsCsvColumns()),
      evictions_csv_(folder_.file("evictions.csv"), evictionsCsvColumns()) {}

void RunOutputs::addStep(const StepRow& r) {
  steps_csv_.cell(r.step)
      .cell(r.t)
      .cell(r.landmarks)
      .cell(r.added)
      .cell(r.dropped)
      .cell(r.poses)
      .cell(r.pose.mean.x)
      .cell(r.pose.mean.y)
      .cell(r.pose.mean.phi)
      .cell(r.pose.cov(0, 0))
      .cell(r.pose.cov(1, 1))
      .cell(r.pose.cov(2, 2))
      .cell(r.step_ms)
      .cell(r.cpu_ms)
      .cell(r.rss_bytes)
      .cell(r.reloc_landmarks)
      .cell(r.reloc_coverage_so_far_pct)
      .cell(r.refused);
  steps_csv_.endRow();
}

void RunOutputs::addEviction(const EvictionRow& e) {
  evictions_csv_.cell(e.step)
      .cell(static_cast<long long>(e.id))
      .cell(e.reducer)
      .cell(e.score)
      .cell(e.n_before)
      .cell(e.n_after)
      .cell(e.reason)
      .cell(shadowChoices(e))
      .cell(shadowErrors(e));
  evictions_csv_.endRow();
}

void RunOutputs::writeState(const Backend& backend, StepIndex step) const {
  const auto lms = backend.landmarks();
  std::vector<VariableKey> vars = {VariableKey::pose(step)};
  for (const auto& l : lms) vars.push_back(VariableKey::landmark(l.id));
  const Eigen::MatrixXd P = backend.jointCovariance(vars);
  const PoseEstimate pose = backend.robotPose();

  std::ostringstream out;
  out << std::setprecision(17);
  out << "# state before the drop event after step " << step << " (backend " << backend.name()
      << ")\n# order: robot x y yaw, then x y of each landmark below\n# ids:";
  for (const auto& l : lms) out << ' ' << l.id;
  out << "\n# mean\n" << pose.mean.x << ' ' << pose.mean.y << ' ' << pose.mean.phi;
  for (const auto& l : lms) out << ' ' << l.mean.x() << ' ' << l.mean.y();
  out << "\n# covariance\n";
  for (Eigen::Index r = 0; r < P.rows(); ++r) {
    for (Eigen::Index c = 0; c < P.cols(); ++c) out << (c ? " " : "") << P(r, c);
    out << '\n';
  }
  writeFileAtomically(folder_.file("states/step_" + std::to_string(step) + ".txt"), out.str());
}

void RunOutputs::writeScene(const std::string& name, const MapContent& map,
                            const Pose2& robot) const {
  writeMapScene(folder_.file(name), map, robot);
}

RunOutputs::EndFilesResult RunOutputs::writeEndFiles(const RunEndFiles& files) {
  EndFilesResult result;
  const auto attempt = [&](const std::string& name, const std::function<void()>& write) {
    try {
      write();
    } catch (const std::exception& e) {
      result.not_written.push_back(name);
      if (result.first_error.empty()) result.first_error = outputFailureLine(e);
    }
  };
  attempt("steps.csv", [&] { steps_csv_.close(); });
  attempt("evictions.csv", [&] { evictions_csv_.close(); });
  attempt("trajectory.tum",
          [&] { writeTrajectoryTum(folder_.file("trajectory.tum"), files.trajectory); });
  attempt("landmarks.csv", [&] {
    writeLandmarksCsv(folder_.file("landmarks.csv"), files.landmarks, files.confirmations);
  });
  // One map content (its k-means included) for both pictures of the final map.
  std::optional<MapContent> map;
  const auto finalMap = [&]() -> const MapContent& {
    if (!map) map = files.map();
    return *map;
  };
  for (const auto format : files.figure_formats) {
    const std::string name = figureFile("map", format);
    attempt(name, [&] { writeMapFigure(folder_.file(name), finalMap(), format); });
  }
  if (files.scene)
    attempt("map.3Dscene", [&] { writeScene("map.3Dscene", finalMap(), files.robot); });
  if (files.truth && !files.truth->path.empty())
    attempt("ground_truth.tum", [&] {
      writeGroundTruthTum(folder_.file("ground_truth.tum"), files.trajectory, *files.truth,
                          files.steps_in_rawlog);
    });
  return result;
}

void RunOutputs::discardStepFiles() {
  for (const std::string& path : {steps_csv_.path(), evictions_csv_.path()}) {
    std::error_code ec;
    std::filesystem::remove(path, ec);  // gone already, or never made: nothing to discard
  }
}

void writeGroundTruthTum(const std::string& path, const std::vector<TrajectoryPoint>& trajectory,
                         const dataset::GroundTruth& truth, std::size_t steps_in_rawlog) {
  const auto gt = metrics::toEstimateFrame(truth);
  std::vector<TrajectoryPoint> rows;
  for (const auto& p : trajectory) {
    const std::size_t row = metrics::groundTruthRow(p.step, gt.path.size(), steps_in_rawlog);
    if (row < gt.path.size()) rows.push_back({p.step, p.t, gt.path[row]});
  }
  writeTrajectoryTum(path, rows);
}

}  // namespace budget_slam::report
