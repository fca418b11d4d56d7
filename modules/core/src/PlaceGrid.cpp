#include "budget_slam/core/PlaceGrid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace budget_slam {

std::size_t PlaceKeyHash::operator()(const PlaceKey& k) const {
  // SplitMix64-style mixing of the three coordinates.
  auto mix = [](std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  };
  return static_cast<std::size_t>(mix(static_cast<std::uint64_t>(k.ix) ^
                                      mix(static_cast<std::uint64_t>(k.iy) ^ mix(k.sector))));
}

PlaceGrid::PlaceGrid(double size, std::size_t sectors) : size_(size), sectors_(sectors) {
  if (!(size > 0) || !std::isfinite(size) || sectors < 1)
    throw std::invalid_argument("PlaceGrid: the cell side must be > 0 and the sectors >= 1");
}

PlaceGrid PlaceGrid::fromSensor(double size_option, std::size_t sectors_option, double max_range,
                                double fov) {
  const double size = size_option > 0 ? size_option : max_range > 0 ? max_range / 4 : 1.0;
  std::size_t sectors = sectors_option;
  if (sectors == 0)
    sectors = fov <= 0 || fov >= 2 * M_PI - 1e-6
                  ? 1  // all around (or unknown): the heading does not change what is in view
                  : static_cast<std::size_t>(std::max(1.0, std::round(4 * M_PI / fov)));
  return PlaceGrid(size, sectors);
}

PlaceKey PlaceGrid::placeOf(const Pose2& pose) const {
  PlaceKey k;
  k.ix = static_cast<std::int64_t>(std::floor(pose.x / size_));
  k.iy = static_cast<std::int64_t>(std::floor(pose.y / size_));
  double yaw = std::fmod(pose.phi, 2 * M_PI);
  if (yaw < 0) yaw += 2 * M_PI;
  const double n = static_cast<double>(sectors_);
  k.sector = static_cast<std::uint32_t>(std::min(n - 1, std::floor(yaw / (2 * M_PI / n))));
  return k;
}

}  // namespace budget_slam
