#pragma once
#include <map>
#include <string>
#include <vector>

#include "../TextTable.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/SensorNoise.h"

namespace budget_slam::dataset::convert {

/// Assembles a pose-and-landmark graph file (iSAM, g2o) into steps. The odometry records must
/// form one chain (each starts where the previous ended); poses and landmarks share one id space.
/// Step k carries the k-th odometry record and the sightings made from its end pose; sightings
/// from the start pose go into an extra first step without odometry (an empty action). Errors are
/// "<file>:<line>: ..." of the record at fault.
class PoseChain {
 public:
  /// `odometry_record` / `sighting_record` name the records in messages ("ODOMETRY", "EDGE_SE2").
  PoseChain(std::string odometry_record, std::string sighting_record);

  void addOdometry(const TextTable& t, long long from, long long to, const OdometryIncrement& inc);
  void addSighting(const TextTable& t, long long pose, long long landmark, double range,
                   double bearing);

  std::size_t odometryCount() const { return odometry_.size(); }
  std::size_t sightingCount() const { return sightings_.size(); }
  /// Every sighting as a reading (for noise statistics and sensor limits).
  std::vector<RangeBearingReading> readings() const;

  /// Checks the sightings against the chain (throws InputError naming the line of the first bad
  /// one) and returns the steps; times are t = k + 1 s (these formats carry none).
  std::vector<Step> build(const TextTable& t, const SensorNoise& noise) const;

 private:
  struct Odometry {
    long long from, to;
    OdometryIncrement inc;
  };
  struct Sighting {
    long long pose, landmark;
    double range, bearing;
    std::size_t line;
  };
  std::string odometry_record_, sighting_record_;
  std::vector<Odometry> odometry_;
  std::vector<Sighting> sightings_;
  std::map<long long, std::size_t> pose_index_;  ///< pose id -> 0 (start) .. odometry count
  std::map<long long, std::size_t> pose_line_;   ///< pose id -> line that introduced it
};

}  // namespace budget_slam::dataset::convert
