#pragma once
#include <Eigen/Core>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "budget_slam/core/Ids.h"

namespace budget_slam::dataset::sim {

struct Wall {
  Eigen::Vector2d a, b;  ///< end points [m]
};

/// Axis-aligned area (a room, a hallway) [m].
struct Region {
  std::string name;
  Eigen::Vector2d lo, hi;
  bool contains(const Eigen::Vector2d& p) const {
    return p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y();
  }
};

struct Landmark {
  LandmarkId id = 0;
  Eigen::Vector2d p;  ///< [m], quantized to 1e-6 m so the ground-truth file holds it exactly
  int region = -1;    ///< >= 0: seen only from inside regions[region]
  int first_lap = 0;  ///< exists from this lap on (0-based) ...
  int last_lap = std::numeric_limits<int>::max();  ///< ... up to and including this lap
};

/// The simulated world: landmarks, walls that occlude, regions that restrict visibility. Queries
/// use uniform grids so that worlds with thousands of landmarks and walls stay fast.
class World {
 public:
  std::vector<Landmark> landmarks;
  std::vector<Wall> walls;
  std::vector<Region> regions;

  /// Builds the grids; call after filling the vectors. cell [m] ~ the sensor's range.
  void index(double cell);
  /// Indices of landmarks within `radius` of p (grid candidates filtered by distance).
  std::vector<std::size_t> near(const Eigen::Vector2d& p, double radius) const;
  /// True when a wall blocks the segment from `from` to `to`.
  bool occluded(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;
  /// Index of the first region holding p, -1 for none.
  int regionOf(const Eigen::Vector2d& p) const;

 private:
  using Cell = std::pair<long, long>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      return std::hash<long>()(c.first * 73856093L ^ c.second * 19349663L);
    }
  };
  Cell cellOf(const Eigen::Vector2d& p) const;
  double cell_ = 1;
  std::unordered_map<Cell, std::vector<std::size_t>, CellHash> landmark_cells_, wall_cells_;
};

/// p rounded to whole micrometres.
Eigen::Vector2d quantize(const Eigen::Vector2d& p);

}  // namespace budget_slam::dataset::sim
