#pragma once
#include <unordered_set>
#include <vector>

#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/core/Pose2.h"

namespace budget_slam::metrics {

/// Where a map can be expected to relocalize a robot: the cells of a square grid within `reach`
/// of a cell the mapping run's path passed through (Chebyshev distance in cells, rounded up),
/// in the map's frame; with reach = the sensor's range, the places from which the robot could
/// read a landmark that the mapping robot could read. A traversal's steps outside it are not
/// scored: no map holds landmarks of places its robot never came near (docs/ALGORITHMS.md
/// "Relocalization: what is scored").
class MappedArea {
 public:
  /// Everywhere (no mapping path known).
  MappedArea() = default;
  /// The area of `path` (poses in the map's frame) on a grid of cell side `cell` [m], > 0,
  /// reaching `reach` [m] (>= 0; at least the path's own cells) around it.
  MappedArea(const std::vector<Pose2>& path, double cell, double reach);

  bool contains(double x, double y) const;
  bool everywhere() const { return cells_.empty(); }
  double cell() const { return cell_; }

 private:
  double cell_ = 1;
  std::unordered_set<PlaceKey, PlaceKeyHash> cells_;  ///< the cells within reach of the path
};

}  // namespace budget_slam::metrics
