#include "PoseChain.h"

#include <set>

#include "ConvertCommon.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset::convert {

PoseChain::PoseChain(std::string odometry_record, std::string sighting_record)
    : odometry_record_(std::move(odometry_record)), sighting_record_(std::move(sighting_record)) {}

void PoseChain::addOdometry(const TextTable& t, long long from, long long to,
                            const OdometryIncrement& inc) {
  const std::string rec = odometry_record_ + " " + std::to_string(from) + " " + std::to_string(to);
  if (from == to) t.fail(rec + " goes from a pose to itself");
  if (odometry_.size() >= limits::kMaxSteps)
    t.fail("more than " + std::to_string(limits::kMaxSteps) + " " + odometry_record_ +
           " records (steps of one conversion)");
  if (odometry_.empty()) {
    pose_index_[from] = 0;
    pose_line_[from] = t.line();
  } else if (from != odometry_.back().to) {
    t.fail(rec + " does not start at pose " + std::to_string(odometry_.back().to) +
           ", where the previous " + odometry_record_ +
           " ended (the odometry must form one chain)");
  }
  if (const auto it = pose_line_.find(to); it != pose_line_.end())
    t.fail(rec + " reaches pose " + std::to_string(to) + " a second time (first on line " +
           std::to_string(it->second) + ")");
  odometry_.push_back({from, to, inc});
  pose_index_[to] = odometry_.size();
  pose_line_[to] = t.line();
}

void PoseChain::addSighting(const TextTable& t, long long pose, long long landmark, double range,
                            double bearing) {
  if (!(range > 0)) t.fail(sighting_record_ + " at zero range has no bearing");
  if (!(range <= limits::kMaxRange))
    t.fail(sighting_record_ + " at a range of " + std::to_string(range) + " m (at most " +
           std::to_string(static_cast<long long>(limits::kMaxRange)) + " m is a reading)");
  sightings_.push_back({pose, landmark, range, bearing, t.line()});
}

std::vector<RangeBearingReading> PoseChain::readings() const {
  std::vector<RangeBearingReading> out;
  out.reserve(sightings_.size());
  for (const auto& s : sightings_) out.push_back({s.landmark, s.range, s.bearing, 0});
  return out;
}

std::vector<Step> PoseChain::build(const TextTable& t, const SensorNoise& noise) const {
  if (odometry_.empty())
    throw InputError(t.path() + ": no " + odometry_record_ + " record (nothing to convert)");
  // Readings grouped by the chain index of the pose they were made from.
  std::vector<std::vector<RangeBearingReading>> at(odometry_.size() + 1);
  std::map<std::pair<long long, long long>, std::size_t> first_line;
  for (const auto& s : sightings_) {
    const auto p = pose_index_.find(s.pose);
    if (p == pose_index_.end())
      throw InputError(t.where(s.line) + ": " + sighting_record_ + " from pose " +
                       std::to_string(s.pose) + ", which no " + odometry_record_ +
                       " record reaches");
    if (const auto l = pose_line_.find(s.landmark); l != pose_line_.end())
      throw InputError(t.where(s.line) + ": landmark id " + std::to_string(s.landmark) +
                       " is also a pose (line " + std::to_string(l->second) + ")");
    const auto key = std::make_pair(s.pose, s.landmark);
    if (const auto d = first_line.find(key); d != first_line.end())
      throw InputError(t.where(s.line) + ": landmark " + std::to_string(s.landmark) +
                       " seen twice from pose " + std::to_string(s.pose) + " (first on line " +
                       std::to_string(d->second) + ")");
    first_line[key] = s.line;
    at[p->second].push_back({s.landmark, s.range, s.bearing, 0});
  }

  std::vector<Step> steps;
  steps.reserve(odometry_.size() + 1);
  auto scanAt = [&](std::size_t pose) {
    RangeBearingScan scan = emptyScan(noise);
    scan.readings = at[pose];
    return scan;
  };
  if (!at[0].empty()) steps.push_back(makeStep(0, 1.0, std::nullopt, scanAt(0)));
  for (std::size_t k = 0; k < odometry_.size(); ++k) {
    const StepIndex i = steps.size();
    steps.push_back(makeStep(i, static_cast<double>(i + 1), odometry_[k].inc, scanAt(k + 1)));
  }
  return steps;
}

}  // namespace budget_slam::dataset::convert
