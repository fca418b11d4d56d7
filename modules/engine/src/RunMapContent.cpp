#include "budget_slam/engine/RunMapContent.h"

#include <unordered_map>

#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/reducers/KMeans.h"

namespace budget_slam::runs {

report::MapContent runMapContent(std::string title, const std::vector<TrajectoryPoint>& trajectory,
                                 const std::vector<LandmarkView>& landmarks,
                                 const reducers::CoverageOptions& clusters,
                                 const std::vector<Eigen::Vector2d>& dropped,
                                 const FinalRelocCoverage* coverage,
                                 const dataset::GroundTruth* truth) {
  report::MapContent map;
  map.title = std::move(title);
  for (const auto& p : trajectory) map.trajectory.push_back(p.pose);
  map.kept = landmarks;
  std::vector<Eigen::Vector2d> obs_means;
  for (const auto& l : landmarks) obs_means.push_back(l.obs_mean);
  for (const std::size_t c :
       reducers::KMeans::cluster(obs_means, clusters.kmeans(obs_means.size())).label)
    map.cluster_of_kept.push_back(static_cast<int>(c));
  map.dropped = dropped;
  // The path coloured by the final map's landmarks in view, when every pose's step is known.
  if (coverage) {
    std::unordered_map<StepIndex, std::size_t> in_view;
    for (const auto& st : coverage->steps) in_view[st.step] = st.in_map;
    map.min_landmarks = coverage->coverage.min_landmarks;
    for (const auto& p : trajectory) {
      const auto it = in_view.find(p.step);
      if (it == in_view.end()) {
        map.trajectory_landmarks.clear();
        break;
      }
      map.trajectory_landmarks.push_back(it->second);
    }
  }
  if (truth && !truth->empty()) {
    const auto gt = metrics::toEstimateFrame(*truth);
    map.ground_truth_path = gt.path;
    for (const auto& [id, l] : gt.landmarks) map.ground_truth_landmarks.push_back(l);
  }
  return map;
}

}  // namespace budget_slam::runs
