#pragma once
#include <cstddef>
#include <cstdint>

#include "budget_slam/core/Pose2.h"

namespace budget_slam {

/// A place: a cell of a square grid in the map's frame and a sector of robot heading (a sensor
/// with a narrow field of view sees other landmarks facing north than facing south).
struct PlaceKey {
  std::int64_t ix = 0, iy = 0;
  std::uint32_t sector = 0;
  bool operator==(const PlaceKey& o) const {
    return ix == o.ix && iy == o.iy && sector == o.sector;
  }
  /// The grid cell alone (sector 0).
  PlaceKey cell() const { return {ix, iy, 0}; }
};

struct PlaceKeyHash {
  std::size_t operator()(const PlaceKey& k) const;
};

/// The geometry of places, shared by the reducers that keep a record by place (place-coverage,
/// localization-information) and by the relocalization score (success per place), so that all
/// three mean the same thing by "a place" (docs/ALGORITHMS.md "place-coverage").
class PlaceGrid {
 public:
  /// A grid with a cell side of `size` [m] (> 0) and `sectors` heading sectors (>= 1).
  PlaceGrid(double size, std::size_t sectors);

  /// The grid from the options and the sensor: `size_option` [m] (0: a quarter of the sensor's
  /// maximum range, so that a place's landmarks stay in view across it; 1 m when the range is
  /// unknown) and `sectors_option` (0: from the field of view, 1 for 360 deg or unknown, else
  /// round(720 deg / fov), e.g. 4 for a 180 deg sensor). `max_range` [m], `fov` [rad]: 0 unknown.
  static PlaceGrid fromSensor(double size_option, std::size_t sectors_option, double max_range,
                              double fov);

  PlaceKey placeOf(const Pose2& pose) const;
  double size() const { return size_; }
  std::size_t sectors() const { return sectors_; }

 private:
  double size_;
  std::size_t sectors_;
};

}  // namespace budget_slam
