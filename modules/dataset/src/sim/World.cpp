#include "World.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace budget_slam::dataset::sim {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Proper intersection of segments pq and ab (touching end points does not count).
bool intersects(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                const Eigen::Vector2d& b) {
  const Eigen::Vector2d r = q - p, s = b - a;
  const double den = cross(r, s);
  if (std::abs(den) < 1e-12) return false;  // parallel: a wall seen edge-on hides nothing
  const double t = cross(a - p, s) / den, u = cross(a - p, r) / den;
  return t > 1e-9 && t < 1 - 1e-9 && u >= 0 && u <= 1;
}

}  // namespace

Eigen::Vector2d quantize(const Eigen::Vector2d& p) {
  return Eigen::Vector2d(std::round(p.x() * 1e6) / 1e6, std::round(p.y() * 1e6) / 1e6);
}

World::Cell World::cellOf(const Eigen::Vector2d& p) const {
  return {static_cast<long>(std::floor(p.x() / cell_)),
          static_cast<long>(std::floor(p.y() / cell_))};
}

void World::index(double cell) {
  cell_ = cell;
  landmark_cells_.clear();
  wall_cells_.clear();
  for (std::size_t i = 0; i < landmarks.size(); ++i)
    landmark_cells_[cellOf(landmarks[i].p)].push_back(i);
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const Cell a = cellOf(walls[i].a.cwiseMin(walls[i].b));
    const Cell b = cellOf(walls[i].a.cwiseMax(walls[i].b));
    for (long x = a.first; x <= b.first; ++x)
      for (long y = a.second; y <= b.second; ++y) wall_cells_[{x, y}].push_back(i);
  }
}

std::vector<std::size_t> World::near(const Eigen::Vector2d& p, double radius) const {
  std::vector<std::size_t> out;
  const Cell lo = cellOf(p - Eigen::Vector2d(radius, radius));
  const Cell hi = cellOf(p + Eigen::Vector2d(radius, radius));
  for (long x = lo.first; x <= hi.first; ++x)
    for (long y = lo.second; y <= hi.second; ++y) {
      const auto it = landmark_cells_.find({x, y});
      if (it == landmark_cells_.end()) continue;
      for (const auto i : it->second)
        if ((landmarks[i].p - p).norm() <= radius) out.push_back(i);
    }
  std::sort(out.begin(), out.end());  // deterministic order: by index = by id
  return out;
}

bool World::occluded(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
  if (walls.empty()) return false;
  // Cells the segment's bounding box covers (walls are short relative to the sensor range).
  const Cell lo = cellOf(from.cwiseMin(to)), hi = cellOf(from.cwiseMax(to));
  std::set<std::size_t> tried;
  for (long x = lo.first; x <= hi.first; ++x)
    for (long y = lo.second; y <= hi.second; ++y) {
      const auto it = wall_cells_.find({x, y});
      if (it == wall_cells_.end()) continue;
      for (const auto i : it->second)
        if (tried.insert(i).second && intersects(from, to, walls[i].a, walls[i].b)) return true;
    }
  return false;
}

int World::regionOf(const Eigen::Vector2d& p) const {
  for (std::size_t i = 0; i < regions.size(); ++i)
    if (regions[i].contains(p)) return static_cast<int>(i);
  return -1;
}

}  // namespace budget_slam::dataset::sim
