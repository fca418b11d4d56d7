#include "budget_slam/report/RunSummaryJson.h"

#include <cmath>

namespace budget_slam::report {

nlohmann::json jsonNumber(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

nlohmann::json groundTruthJson(const dataset::GroundTruth& truth,
                               const metrics::GroundTruthErrors& e, const metrics::NeesMean& nees,
                               const std::optional<metrics::MapAlignment>& alignment) {
  nlohmann::json j = {{"landmarks_file", truth.landmarks_file},
                      {"path_file", truth.path_file},
                      {"poses", e.poses},
                      {"trajectory_rmse_m", jsonNumber(e.trajectory_rmse)},
                      {"trajectory_max_m", jsonNumber(e.trajectory_max)},
                      {"trajectory_rmse_aligned_m", jsonNumber(e.trajectory_rmse_aligned)},
                      {"alignment_rotation_deg", jsonNumber(e.alignment_rotation_deg)},
                      {"trajectory_rpe_10m_m", jsonNumber(e.rpe.rmse)},
                      {"trajectory_rpe_10m_max_m", jsonNumber(e.rpe.max)},
                      {"rpe_pairs", e.rpe.pairs},
                      {"landmark_rmse_aligned_m", jsonNumber(e.landmark_rmse_aligned)},
                      {"landmarks", e.landmarks},
                      {"landmark_rmse_m", jsonNumber(e.landmark_rmse)},
                      {"nees_mean", jsonNumber(nees.mean)},
                      {"nees_samples", nees.samples}};
  if (alignment)
    j["map_alignment"] = {{"x", alignment->transform.t.x()},
                          {"y", alignment->transform.t.y()},
                          {"yaw", alignment->yaw()},
                          {"source", alignment->source},
                          {"points", alignment->points}};
  return j;
}

nlohmann::json relocalizationJson(const metrics::RelocalizationCoverage& c,
                                  const std::string& source, const nlohmann::json& details) {
  nlohmann::json r = {{"min_landmarks", c.min_landmarks},
                      {"coverage_pct", jsonNumber(c.coverage_pct)},
                      {"mean_landmarks", jsonNumber(c.mean_landmarks)},
                      {"steps", c.steps},
                      {"steps_covered", c.steps_covered},
                      {"sampled", c.sampled},
                      {"source", source}};
  for (const auto& [k, v] : details.items()) r[k] = v;
  return r;
}

}  // namespace budget_slam::report
