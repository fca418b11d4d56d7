#include "budget_slam/graph/GraphBackend.h"

namespace budget_slam::graph {

BackendEntry GraphBackend::entry() {
  return {
      kName,
      "landmark graph SLAM: every kept pose, sparse Cholesky (CHOLMOD), docs/GRAPH.md",
      {tabledSection<GraphSlamOptions>(), tabledSection<RangeBearingNoise>()},
      // The graph's estimate is its trajectory: BackendSettings::keep_trajectory does not apply.
      [](const mrpt::config::CConfigFileBase& ini, const BackendSettings&) {
        return std::unique_ptr<Backend>(std::make_unique<GraphBackend>(ini));
      }};
}

}  // namespace budget_slam::graph
