#include "budget_slam/reducers/HindsightReducer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/RawlogReader.h"

namespace budget_slam::reducers {
namespace {

using O = HindsightOptions;

/// The `keep` key: checked when read, so that a bad value stops the run before its first step.
OptionKey<O> keepKey() {
  return {"keep",
          [](O& o, const IniSection& s) {
            o.keep = s.readString("keep", o.keep);
            O::keepCount(o.keep, 1);
          },
          [](const O& o) { return o.keep; }, "landmarks, or P% of the final map"};
}

}  // namespace

const OptionTable<HindsightOptions>& HindsightOptions::table() {
  static const OptionTable<O> t = {
      keepKey(),
      option::list("places_rawlogs", &O::places_rawlogs,
                   "rawlogs with a ground-truth path; empty = this run's places"),
  };
  return t;
}

std::size_t HindsightOptions::keepCount(const std::string& keep, std::size_t n) {
  const auto bad = [&](const std::string& why) {
    return KeyError::ofValue(kSection, "keep", keep, why);
  };
  if (keep.empty()) throw bad("empty (a number of landmarks, or a percentage like 20%)");
  char* end = nullptr;
  if (keep.back() == '%') {
    const std::string number = keep.substr(0, keep.size() - 1);
    const double p = std::strtod(number.c_str(), &end);
    if (number.empty() || *end != '\0' || !(p > 0) || p > 100)
      throw bad("not a percentage in (0, 100]");
    const double k = std::floor(p / 100.0 * static_cast<double>(n) + 0.5);
    return std::max<std::size_t>(1, static_cast<std::size_t>(k));
  }
  const long long k = std::strtoll(keep.c_str(), &end, 10);
  if (*end != '\0' || k < 1 || k > 100000000) throw bad("not a number of landmarks >= 1");
  return static_cast<std::size_t>(k);
}

HindsightReducer::HindsightReducer(HindsightOptions options,
                                   std::unique_ptr<LocalizationInformationReducer> record,
                                   std::unique_ptr<LocalizationInformationReducer> future)
    : options_(std::move(options)), record_(std::move(record)), future_(std::move(future)) {}

void HindsightReducer::dumpOptions(std::ostream& out) const { options_.dumpToTextStream(out); }

std::vector<PlaceReadings> HindsightReducer::places() const {
  return future_ ? future_->placeReadings() : record_->placeReadings();
}

ScheduledDrops HindsightReducer::scheduled(const ScheduleContext& ctx) {
  ScheduledDrops out;
  out.reason = "hindsight";
  if (!ctx.final) return out;
  std::vector<LandmarkId> map;
  for (const LandmarkView& l : ctx.backend.landmarks()) map.push_back(l.id);
  const std::size_t k = HindsightOptions::keepCount(options_.keep, map.size());
  // The prior of the record the places come from (both follow the same sections).
  const Eigen::Matrix3d& prior = future_ ? future_->prior() : record_->prior();
  selection_places_ = places();
  selection_ = greedyLogDetSelection(selection_places_, prior, map, k);
  for (const LandmarkId id : map)
    if (!std::binary_search(selection_.selection.begin(), selection_.selection.end(), id))
      out.drops.push_back({id, 0.0});
  return out;
}

void recordTraversal(const std::string& rawlog, LocalizationInformationReducer& record,
                     StepIndex& step_counter) {
  const auto bad = [&](const std::string& why) {
    return KeyError::ofValue(HindsightOptions::kSection, "places_rawlogs", rawlog, why);
  };
  try {
    const dataset::GroundTruth truth = dataset::loadGroundTruth(rawlog);
    if (truth.path.empty()) throw bad("no ground-truth robot path beside it");
    dataset::RawlogReader reader(rawlog);
    while (const auto step = reader.next()) {
      if (!step->scan) continue;
      if (step->index >= truth.path.size())
        throw bad("step " + std::to_string(step->index) + " has no row in " + truth.path_file);
      StepObservation seen;
      seen.step = step_counter++;
      seen.robot = truth.path[step->index];
      const auto& s = step->scan->sensor_pose_on_robot;
      seen.sensor_pose = Pose2(s.x, s.y, s.yaw);
      seen.sensor_max_range = step->scan->max_range;
      seen.sensor_fov = step->scan->fov_yaw;
      for (const auto& r : step->scan->readings)
        if (r.id != kNoLandmarkId) {
          seen.observed.push_back(r.id);
          seen.sightings.push_back({r.id, r.range, r.yaw});
        }
      record.observe(seen);
    }
  } catch (const KeyError&) {
    throw;
  } catch (const std::exception& e) {
    throw bad(e.what());
  }
}

ReducerRegistry::Entry HindsightReducer::entry() {
  std::vector<OptionSection> sections = {tabledSection<HindsightOptions>()};
  for (auto& s : LocalizationInformationReducer::sections()) sections.push_back(std::move(s));
  return {kName,
          "not a rule: the best map of `keep` landmarks with hindsight (greedy on "
          "localization-information's objective over the whole run's places, or over "
          "places_rawlogs'), chosen after the last step of an unreduced run",
          sections, [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
            HindsightOptions o;
            o.loadFromConfigFile(ini, HindsightOptions::kSection);
            std::unique_ptr<LocalizationInformationReducer> future;
            if (!o.places_rawlogs.empty()) {
              future = LocalizationInformationReducer::fromIni(ini);
              StepIndex step = 0;
              for (const std::string& f : o.places_rawlogs) recordTraversal(f, *future, step);
            }
            return std::make_unique<HindsightReducer>(
                o, LocalizationInformationReducer::fromIni(ini), std::move(future));
          }};
}

}  // namespace budget_slam::reducers
