#include "budget_slam/metrics/MappedArea.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::metrics {

MappedArea::MappedArea(const std::vector<Pose2>& path, double cell, double reach) : cell_(cell) {
  const PlaceGrid grid(cell, 1);
  const auto r = static_cast<std::int64_t>(std::ceil(std::max(0.0, reach) / cell));
  std::unordered_set<PlaceKey, PlaceKeyHash> visited;
  for (const auto& p : path) visited.insert(grid.placeOf(p));
  for (const PlaceKey& k : visited)
    for (std::int64_t dx = -r; dx <= r; ++dx)
      for (std::int64_t dy = -r; dy <= r; ++dy) cells_.insert({k.ix + dx, k.iy + dy, 0});
}

bool MappedArea::contains(double x, double y) const {
  return cells_.empty() || cells_.count(PlaceGrid(cell_, 1).placeOf({x, y, 0})) > 0;
}

}  // namespace budget_slam::metrics
