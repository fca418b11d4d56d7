#include "budget_slam/reducers/CoverageSelection.h"

#include <algorithm>
#include <limits>

namespace budget_slam::reducers {

KMeans::Result coverageClusters(const std::vector<LandmarkView>& landmarks,
                                const CoverageOptions& options) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(landmarks.size());
  for (const auto& l : landmarks) points.push_back(l.obs_mean);
  return KMeans::cluster(points, options.kmeans(points.size()));
}

ClusterPick pickByClusterSpread(const DropContext& ctx, const std::vector<std::size_t>& label,
                                const std::vector<double>& s, Spread spread) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const std::size_t k = label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1;
  std::vector<double> max_member(k, -inf), min_member(k, inf);
  for (std::size_t i = 0; i < ctx.landmarks.size(); ++i) {
    max_member[label[i]] = std::max(max_member[label[i]], s[i]);
    min_member[label[i]] = std::min(min_member[label[i]], s[i]);
  }
  // The lowest-s candidate of each cluster (ties to the lowest id).
  std::vector<std::size_t> worst(k, ctx.landmarks.size());
  for (const std::size_t i : ctx.candidates) {
    std::size_t& w = worst[label[i]];
    if (w == ctx.landmarks.size() || s[i] < s[w] ||
        (s[i] == s[w] && ctx.landmarks[i].id < ctx.landmarks[w].id))
      w = i;
  }
  ClusterPick best;
  bool found = false;
  for (std::size_t c = 0; c < k; ++c) {
    const std::size_t w = worst[c];
    if (w == ctx.landmarks.size()) continue;  // no candidate in this cluster
    const double d =
        spread == Spread::Members ? max_member[c] - min_member[c] : max_member[c] - s[w];
    const ClusterPick p{ctx.landmarks[w].id, s[w], c, d};
    if (!found || p.spread > best.spread ||
        (p.spread == best.spread &&
         (p.score < best.score || (p.score == best.score && p.id < best.id))))
      best = p;
    found = true;
  }
  return best;
}

}  // namespace budget_slam::reducers
