#include "budget_slam/reducers/LocalizationInformationReducer.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <set>
#include <tuple>
#include <vector>

#include "ReducerSession.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/RangeBearingModel.h"

namespace budget_slam::reducers {

namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kInf = std::numeric_limits<double>::infinity();
/// The prior's sigma in x and y when the rawlog states no sensor range [m].
constexpr double kPriorWithoutRange = 10.0;

const EnumNames<LocalizationInformationOptions::Objective>& objectiveNames() {
  using O = LocalizationInformationOptions::Objective;
  static const EnumNames<O> n = {{"sum_log_det", O::SumLogDet}, {"min_log_det", O::MinLogDet}};
  return n;
}

/// log det of a symmetric positive definite 3x3 matrix.
double logDet(const Eigen::Matrix3d& m) {
  const Eigen::LLT<Eigen::Matrix3d> llt(m);
  const Eigen::Matrix3d& L = llt.matrixLLT();
  return 2 * (std::log(L(0, 0)) + std::log(L(1, 1)) + std::log(L(2, 2)));
}

/// Symmetric to round-off (relative 1e-9) and positive definite.
bool isSpd(const Eigen::Matrix3d& m) {
  const double scale = m.cwiseAbs().maxCoeff();
  if (!((m - m.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) return false;
  const Eigen::LLT<Eigen::Matrix3d> llt(m);
  return llt.info() == Eigen::Success && llt.matrixLLT().allFinite() &&
         llt.matrixLLT().diagonal().minCoeff() > 0;
}

/// Symmetric to round-off and positive semi-definite (eigenvalues >= -1e-9 x the largest).
bool isPsd(const Eigen::Matrix3d& m) {
  const double scale = m.cwiseAbs().maxCoeff();
  if (scale == 0) return true;
  if (!((m - m.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m, Eigen::EigenvaluesOnly);
  return eig.info() == Eigen::Success && eig.eigenvalues().minCoeff() >= -1e-9 * scale;
}

}  // namespace

const OptionTable<LocalizationInformationOptions>& LocalizationInformationOptions::table() {
  using O = LocalizationInformationOptions;
  static const OptionTable<O> t = {
      option::choice("objective", &O::objective, objectiveNames(), "sum_log_det | min_log_det"),
      option::real("prior_std_xy", &O::prior_std_xy, 0.0, 1e6,
                   "[m], 0 = the sensor's maximum range"),
      option::real("prior_std_yaw_deg", &O::prior_std_yaw_deg, 1e-6, 1e6, "[deg]"),
      option::real("place_size", &O::place_size, 0.0, 1e6, "[m], 0 = from the sensor's range"),
      option::integer("heading_sectors", &O::heading_sectors, 0, 360,
                      "0 = from the sensor's field of view"),
      option::integer("max_places", &O::max_places, 1, 100000000, "[places]"),
      option::integer("remember_dropped", &O::remember_dropped, 0, 100000000,
                      "[landmarks], 0 = forget at once"),
      option::flag("second_landmark_admission", &O::second_landmark_admission,
                   "compete: a newcomer that is a place's second landmark goes last"),
  };
  return t;
}

LocalizationInformationReducer::LocalizationInformationReducer(
    const LocalizationInformationOptions& options, double std_range, double std_bearing)
    : options_(options),
      std_range_(std_range),
      std_bearing_(std_bearing),
      slots_(options.max_places) {}

void LocalizationInformationReducer::fixGeometry(const StepObservation& seen) {
  if (grid_) return;
  grid_ = PlaceGrid::fromSensor(options_.place_size, options_.heading_sectors,
                                seen.sensor_max_range, seen.sensor_fov);
  const double sxy = options_.prior_std_xy > 0   ? options_.prior_std_xy
                     : seen.sensor_max_range > 0 ? seen.sensor_max_range
                                                 : kPriorWithoutRange;
  const double syaw = options_.prior_std_yaw_deg * kDeg;
  prior_ = Eigen::Vector3d(1 / (sxy * sxy), 1 / (sxy * sxy), 1 / (syaw * syaw)).asDiagonal();
}

void LocalizationInformationReducer::addReading(std::uint32_t slot, const StepObservation& seen,
                                                const Sighting& r, bool active) {
  // The landmark where the reading puts it, and the reading's information at that geometry.
  const Pose2 robot = seen.robot, sensor = seen.sensor_pose;
  const Eigen::Vector2d at = robot.transformFrom(readingPoint(r.range, r.bearing, sensor));
  if (!(r.range > 0) || !at.allFinite()) return;
  const auto H = predictRangeBearing(robot, sensor, at).H_robot;
  const Eigen::Matrix3d info = readingInformation(H, std_range_, std_bearing_);
  Place& p = places_[slot];
  auto it = std::lower_bound(p.entries.begin(), p.entries.end(), r.id,
                             [](const Entry& e, LandmarkId id) { return e.id < id; });
  if (it == p.entries.end() || it->id != r.id) {
    it = p.entries.insert(it, Entry{r.id});
    it->active = active;
    places_of_[r.id].push_back(slot);
  }
  it->info_sum += info;
  it->readings += 1;
  if (it->active) markDirty(slot);
}

void LocalizationInformationReducer::observe(const StepObservation& seen) {
  fixGeometry(seen);
  const bool withheld = options_.remember_dropped > 0 && !seen.withheld.empty();
  if (seen.sightings.empty() && !withheld) return;  // no landmark read: no choice constrained
  const std::uint32_t slot = slots_.visit(grid_->placeOf(seen.robot), seen.step,
                                          [this](std::uint32_t gone) { forgetPlace(gone); });
  places_.resize(slots_.slots());
  for (const Sighting& r : seen.sightings) {
    if (dropped_at_.count(r.id)) {  // back in the map: every place on record counts again
      dropped_.erase(dropped_at_.at(r.id));
      dropped_at_.erase(r.id);
      setActive(r.id, true);
    }
    addReading(slot, seen, r, true);
  }
  if (!withheld) return;
  for (const Sighting& r : seen.withheld) {
    const auto on_map = places_of_.find(r.id);
    if (on_map != places_of_.end() && !dropped_at_.count(r.id))
      continue;  // in the map: not withheld
    addReading(slot, seen, r, false);
    remember(r.id);
  }
}

void LocalizationInformationReducer::setActive(LandmarkId id, bool active) {
  const auto it = places_of_.find(id);
  if (it == places_of_.end()) return;
  for (const std::uint32_t slot : it->second) {
    Place& p = places_[slot];
    for (Entry& e : p.entries)
      if (e.id == id && e.active != active) {
        e.active = active;
        markDirty(slot);
      }
  }
}

void LocalizationInformationReducer::remember(LandmarkId id) {
  const auto at = dropped_at_.find(id);
  if (at != dropped_at_.end()) dropped_.erase(at->second);
  dropped_.push_back(id);
  dropped_at_[id] = std::prev(dropped_.end());
  while (dropped_.size() > options_.remember_dropped) {
    const LandmarkId oldest = dropped_.front();
    dropped_.pop_front();
    dropped_at_.erase(oldest);
    eraseLandmark(oldest);
  }
}

void LocalizationInformationReducer::eraseLandmark(LandmarkId id) {
  const auto it = places_of_.find(id);
  if (it == places_of_.end()) return;
  for (const std::uint32_t slot : it->second) {
    Place& p = places_[slot];
    const auto e = std::find_if(p.entries.begin(), p.entries.end(),
                                [&](const Entry& x) { return x.id == id; });
    if (e->active) markDirty(slot);
    p.entries.erase(e);
  }
  places_of_.erase(it);
}

void LocalizationInformationReducer::forget(LandmarkId id) {
  if (!places_of_.count(id)) return;
  if (options_.remember_dropped == 0) {
    eraseLandmark(id);
    return;
  }
  setActive(id, false);
  remember(id);
}

void LocalizationInformationReducer::forgetPlace(std::uint32_t slot) {
  for (const Entry& e : places_[slot].entries) {
    auto& slots = places_of_[e.id];
    slots.erase(std::find(slots.begin(), slots.end(), slot));
    if (slots.empty()) {
      places_of_.erase(e.id);
      const auto at = dropped_at_.find(e.id);
      if (at != dropped_at_.end()) dropped_.erase(at->second), dropped_at_.erase(at);
    }
  }
  places_[slot] = Place();
}

void LocalizationInformationReducer::markDirty(std::uint32_t slot) {
  if (places_[slot].dirty) return;
  places_[slot].dirty = true;
  dirty_.push_back(slot);
}

void LocalizationInformationReducer::refresh() const {
  for (const std::uint32_t slot : dirty_) {
    Place& p = places_[slot];
    if (!p.dirty || !slots_.used(slot)) continue;
    p.lambda = prior_;
    for (const Entry& e : p.entries)
      if (e.active) p.lambda += e.info_sum / e.readings;
    p.logdet = logDet(p.lambda);
    for (Entry& e : p.entries)
      if (e.active) e.without = logDet(p.lambda - e.info_sum / e.readings);
    p.dirty = false;
  }
  dirty_.clear();
}

const LocalizationInformationReducer::Entry* LocalizationInformationReducer::entryOf(
    const Place& p, LandmarkId id) const {
  const auto it = std::lower_bound(p.entries.begin(), p.entries.end(), id,
                                   [](const Entry& e, LandmarkId v) { return e.id < v; });
  return it != p.entries.end() && it->id == id ? &*it : nullptr;
}

Eigen::Matrix3d LocalizationInformationReducer::placeInformation(const Pose2& robot) const {
  refresh();
  const auto slot = grid_ ? slots_.find(grid_->placeOf(robot)) : std::nullopt;
  return slot ? places_[*slot].lambda : prior_;
}

double LocalizationInformationReducer::objective() const {
  refresh();
  double f = 0;
  for (std::uint32_t s = 0; s < places_.size(); ++s)
    if (slots_.used(s)) f += places_[s].logdet;
  return f;
}

std::vector<PlaceReadings> LocalizationInformationReducer::placeReadings() const {
  std::vector<PlaceReadings> out;
  for (std::uint32_t s = 0; s < places_.size(); ++s) {
    if (!slots_.used(s)) continue;
    PlaceReadings p;
    for (const Entry& e : places_[s].entries)
      if (e.active) p.ids.push_back(e.id), p.info.push_back(e.info_sum / e.readings);
    if (!p.ids.empty()) out.push_back(std::move(p));
  }
  return out;
}

double LocalizationInformationReducer::leastPlace() const {
  refresh();
  double m = kInf;
  for (std::uint32_t s = 0; s < places_.size(); ++s)
    if (slots_.used(s)) m = std::min(m, places_[s].logdet);
  return m;
}

double LocalizationInformationReducer::loss(LandmarkId id) const {
  refresh();
  const auto it = places_of_.find(id);
  if (it == places_of_.end() || dropped_at_.count(id)) return 0;
  double sum = 0;
  for (const std::uint32_t slot : it->second) {
    const Place& p = places_[slot];
    sum += p.logdet - entryOf(p, id)->without;
  }
  return sum;
}

double LocalizationInformationReducer::minLoss(LandmarkId id) const {
  // Removing l lowers only its places, so the least place after is min(m, least of its places
  // without it): the loss of the minimum is max(0, m - that least).
  refresh();
  const auto it = places_of_.find(id);
  if (it == places_of_.end() || dropped_at_.count(id)) return 0;
  double least_without = kInf;
  for (const std::uint32_t slot : it->second)
    least_without = std::min(least_without, entryOf(places_[slot], id)->without);
  const double m = leastPlace(), drop = m - least_without;
  // A place left with the prior alone computes its log det as a difference: round-off is no loss.
  return drop > 1e-9 * std::max(1.0, std::abs(m)) ? drop : 0.0;
}

std::size_t LocalizationInformationReducer::secondLandmarkPlaces(LandmarkId id) const {
  const auto it = places_of_.find(id);
  if (it == places_of_.end() || dropped_at_.count(id)) return 0;
  std::size_t n = 0;
  for (const std::uint32_t slot : it->second) {
    const auto& entries = places_[slot].entries;
    n +=
        std::count_if(entries.begin(), entries.end(), [](const Entry& e) { return e.active; }) == 2;
  }
  return n;
}

ReducerChoice LocalizationInformationReducer::choose(const DropContext& ctx) {
  refresh();
  const bool by_min = options_.objective == LocalizationInformationOptions::Objective::MinLogDet;
  struct Scored {
    double key, sum;
    LandmarkId id;
  };
  // second_landmark_admission: a newcomer (it entered at this step; a candidate only under
  // admission = compete) that gives one of its places its second map landmark is admitted unless
  // every candidate is one. Waking up and relocalizing need two landmarks in one view, and a
  // newcomer's loss counts the few places it was read from so far, against the many of a landmark
  // that has been in the map for long: without this, a place's second landmark is refused as
  // readily as a third.
  const auto admitted = [&](std::size_t i) {
    return options_.second_landmark_admission && ctx.landmarks[i].first_step == ctx.step &&
           secondLandmarkPlaces(ctx.landmarks[i].id) > 0;
  };
  const bool all_admitted = std::all_of(ctx.candidates.begin(), ctx.candidates.end(), admitted);
  std::vector<Scored> scored;
  double least = kInf;
  for (const std::size_t i : ctx.candidates) {
    if (!all_admitted && admitted(i)) continue;
    const LandmarkId id = ctx.landmarks[i].id;
    const double sum = loss(id);
    scored.push_back({by_min ? minLoss(id) : sum, sum, id});
    least = std::min(least, scored.back().key);
  }
  // The least loss goes; losses equal up to round-off (1e-9 relative) are ties, decided by the
  // sum's loss, then the lowest id.
  const double tie = least + 1e-9 * std::max(1.0, std::abs(least));
  const Scored* best = nullptr;
  for (const Scored& c : scored)
    if (c.key <= tie && (!best || std::tie(c.sum, c.id) < std::tie(best->sum, best->id))) best = &c;
  return {best->id, best->key};
}

namespace {

/// The sensor noise the filter assumes, [RangeBearingKFSLAM] std_sensor_range [m] and
/// std_sensor_yaw_deg [deg] (MRPT's defaults: 0.1 m, 0.5 deg), checked as the filter checks it.
struct SensorNoise {
  double std_range = 0.1, std_yaw_deg = 0.5;
};
constexpr const char* kSensorSection = "RangeBearingKFSLAM";

SensorNoise readSensorNoise(const mrpt::config::CConfigFileBase& ini) {
  const IniSection sensor(ini, kSensorSection);
  SensorNoise n;
  n.std_range = sensor.readDouble("std_sensor_range", n.std_range, 0, 1e6);
  n.std_yaw_deg = sensor.readDouble("std_sensor_yaw_deg", n.std_yaw_deg, 0, 360);
  return n;
}

}  // namespace

std::vector<OptionSection> LocalizationInformationReducer::sections() {
  const SensorNoise defaults;
  return {tabledSection<LocalizationInformationOptions>(),
          {kSensorSection,
           {{"std_sensor_range", option::numberText(defaults.std_range), "[m], >= 0"},
            {"std_sensor_yaw_deg", option::numberText(defaults.std_yaw_deg), "[deg], 0 to 360"}},
           [](const mrpt::config::CConfigFileBase& ini) { readSensorNoise(ini); }}};
}

std::unique_ptr<LocalizationInformationReducer> LocalizationInformationReducer::fromIni(
    const mrpt::config::CConfigFileBase& ini) {
  LocalizationInformationOptions o;
  o.loadFromConfigFile(ini, LocalizationInformationOptions::kSection);
  // A noise of 0 is read as 1e-12 (the information is finite).
  const SensorNoise n = readSensorNoise(ini);
  return std::make_unique<LocalizationInformationReducer>(o, std::max(n.std_range, 1e-12),
                                                          std::max(n.std_yaw_deg * kDeg, 1e-12));
}

ReducerRegistry::Entry LocalizationInformationReducer::entry() {
  return {kName,
          "keep the landmarks that tell the robot most about its pose at every visited place: "
          "greedy on the sum over places of log det of the pose's Fisher information",
          sections(), [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
            return std::unique_ptr<Reducer>(fromIni(ini));
          }};
}

void LocalizationInformationReducer::saveSession(session::SessionState& state) const {
  session::SessionSection& s = state.section(reducerSection(name()));
  putGrid(s, grid_);
  s.putReals("prior", std::vector<double>(prior_.data(), prior_.data() + 9));
  slots_.save(s);
  // Every place's entries in turn (exact values, the cached ones included, so that a resumed run
  // refreshes the same places at the same steps).
  std::vector<std::vector<LandmarkId>> entry_ids;
  std::vector<double> info, readings, without, lambda, logdet;
  std::vector<std::int64_t> active, dirty;
  for (const Place& p : places_) {
    std::vector<LandmarkId> ids;
    for (const Entry& e : p.entries) {
      ids.push_back(e.id);
      info.insert(info.end(), e.info_sum.data(), e.info_sum.data() + 9);
      readings.push_back(e.readings);
      without.push_back(e.without);
      active.push_back(e.active ? 1 : 0);
    }
    entry_ids.push_back(std::move(ids));
    lambda.insert(lambda.end(), p.lambda.data(), p.lambda.data() + 9);
    logdet.push_back(p.logdet);
    dirty.push_back(p.dirty ? 1 : 0);
  }
  putNested(s, "entry_ids", entry_ids);
  s.putReals("entry_info", std::move(info));
  s.putReals("entry_readings", std::move(readings));
  s.putReals("entry_without", std::move(without));
  s.putIntegers("entry_active", std::move(active));
  s.putReals("place_lambda", std::move(lambda));
  s.putReals("place_logdet", std::move(logdet));
  s.putIntegers("place_dirty", std::move(dirty));
  s.putIntegers("dirty_slots", std::vector<std::int64_t>(dirty_.begin(), dirty_.end()));
  std::vector<LandmarkId> ids;
  for (const auto& [id, slots] : places_of_) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  std::vector<std::vector<std::uint32_t>> slots_of;
  for (const LandmarkId id : ids) slots_of.push_back(places_of_.at(id));
  s.putIntegers("landmark_ids", std::vector<std::int64_t>(ids.begin(), ids.end()));
  putNested(s, "landmark_places", slots_of);
  s.putIntegers("dropped_ids", std::vector<std::int64_t>(dropped_.begin(), dropped_.end()));
}

void LocalizationInformationReducer::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take(reducerSection(name()));
  constexpr std::int64_t kMaxId = std::numeric_limits<std::int64_t>::max();
  grid_ = readGrid(s);
  const auto& prior = s.reals("prior", 9);
  prior_ = Eigen::Map<const Eigen::Matrix3d>(prior.data());
  slots_.restore(s);
  const std::size_t n = slots_.slots();
  const auto ids = nested(s, "entry_ids", n, 0, kMaxId);
  std::size_t entries = 0;
  for (const auto& l : ids) entries += l.size();
  const auto& info = s.reals("entry_info", 9 * entries);
  const auto& readings = s.reals("entry_readings", entries);
  const auto& without = s.reals("entry_without", entries);
  const auto& active = s.integers("entry_active", entries, 0, 1);
  const auto& lambda = s.reals("place_lambda", 9 * n);
  const auto& logdet = s.reals("place_logdet", n);
  const auto& dirty = s.integers("place_dirty", n, 0, 1);
  places_.assign(n, Place());
  std::size_t e = 0;
  for (std::size_t k = 0; k < n; ++k) {
    Place& p = places_[k];
    for (const auto id : ids[k]) {
      Entry x;
      x.id = id;
      x.info_sum = Eigen::Map<const Eigen::Matrix3d>(info.data() + 9 * e);
      x.readings = readings[e];
      x.without = without[e];
      x.active = active[e] != 0;
      p.entries.push_back(x);
      ++e;
    }
    p.lambda = Eigen::Map<const Eigen::Matrix3d>(lambda.data() + 9 * k);
    p.logdet = logdet[k];
    p.dirty = dirty[k] != 0;
  }
  const auto& dirty_slots = s.integers("dirty_slots", s.integers("dirty_slots").size(), 0,
                                       static_cast<std::int64_t>(n) - 1);
  dirty_.assign(dirty_slots.begin(), dirty_slots.end());
  const auto& lm = s.integers("landmark_ids");
  const auto lm_places =
      nested(s, "landmark_places", lm.size(), 0, static_cast<std::int64_t>(n) - 1);
  places_of_.clear();
  for (std::size_t i = 0; i < lm.size(); ++i)
    places_of_[lm[i]].assign(lm_places[i].begin(), lm_places[i].end());
  dropped_.clear();
  dropped_at_.clear();
  for (const auto id : s.integers("dropped_ids")) {
    if (dropped_at_.count(id)) s.fail("dropped_ids", "landmark " + std::to_string(id) + " twice");
    dropped_.push_back(id);
    dropped_at_[id] = std::prev(dropped_.end());
  }
  checkRestored(s, lm, state);
}

void LocalizationInformationReducer::checkRestored(const session::SessionSection& s,
                                                   const std::vector<std::int64_t>& landmark_ids,
                                                   const session::SessionState& state) const {
  // A CRC proves the file whole, not sane: every cross-reference between the places' entries and
  // the landmarks' places is checked here, before loss(), forgetPlace() and eraseLandmark()
  // follow them without looking (a landmark listed at a place that has no entry for it would be
  // dereferenced as a null entry).
  const auto id = [](LandmarkId v) { return std::to_string(v); };
  // The information matrices: the prior positive definite, each entry's sum of readings'
  // information symmetric positive semi-definite, so that every place's information and every
  // "without" matrix is positive definite and its log det a number (a NaN key would leave
  // choose() without a candidate).
  if (!isSpd(prior_)) s.fail("prior", "not symmetric positive definite");
  std::size_t entries = 0;
  for (std::uint32_t k = 0; k < places_.size(); ++k) {
    const Place& p = places_[k];
    if (!slots_.used(k) && !p.entries.empty())
      s.fail("entry_ids", "place " + std::to_string(k) + " is free but holds " +
                              std::to_string(p.entries.size()) + " entries");
    for (std::size_t e = 0; e < p.entries.size(); ++e) {
      if (e > 0 && !(p.entries[e - 1].id < p.entries[e].id))
        s.fail("entry_ids", "the entries of place " + std::to_string(k) +
                                " are not in increasing id order (" + id(p.entries[e - 1].id) +
                                " before " + id(p.entries[e].id) + ")");
      if (!isPsd(p.entries[e].info_sum))
        s.fail("entry_info", "the entry of landmark " + id(p.entries[e].id) + " at place " +
                                 std::to_string(k) + " is not symmetric positive semi-definite");
      if (!(p.entries[e].readings >= 1))
        s.fail("entry_readings", "an entry of place " + std::to_string(k) + " has " +
                                     option::numberText(p.entries[e].readings) +
                                     " readings (at least 1)");
    }
    entries += p.entries.size();
  }
  std::set<LandmarkId> on_map;
  for (const auto& l : state.map.landmarks) on_map.insert(l.id);
  std::size_t listed = 0;
  for (std::size_t i = 0; i < landmark_ids.size(); ++i) {
    const LandmarkId l = landmark_ids[i];
    if (i > 0 && !(landmark_ids[i - 1] < l))
      s.fail("landmark_ids",
             "not in increasing order (" + id(landmark_ids[i - 1]) + " before " + id(l) + ")");
    const auto& slots = places_of_.at(l);
    if (slots.empty()) s.fail("landmark_places", "landmark " + id(l) + " has no place");
    const bool dropped = dropped_at_.count(l) > 0;
    std::set<std::uint32_t> distinct;
    for (const std::uint32_t k : slots) {
      if (!distinct.insert(k).second)
        s.fail("landmark_places",
               "landmark " + id(l) + " lists place " + std::to_string(k) + " twice");
      const Entry* e = entryOf(places_[k], l);
      if (!e)
        s.fail("landmark_places", "landmark " + id(l) + " lists place " + std::to_string(k) +
                                      ", which has no entry for it");
      // Forgetting sets every entry of a landmark inactive at once, seeing it again active.
      if (e->active == dropped)
        s.fail("entry_active", "landmark " + id(l) + " is " + (e->active ? "active" : "inactive") +
                                   " at place " + std::to_string(k) + " but " +
                                   (dropped ? "on" : "not on") + " the dropped list");
      if (e->active && !on_map.count(l))
        s.fail("entry_ids", "landmark " + id(l) + " is active at place " + std::to_string(k) +
                                " but not in the map of the state's [landmarks]");
    }
    listed += slots.size();
  }
  // Each listed (landmark, place) has its entry and no pair is listed twice: with as many entries
  // as listed pairs, every entry is listed too.
  if (listed != entries)
    s.fail("landmark_places", std::to_string(listed) + " places listed for the landmarks, " +
                                  std::to_string(entries) + " entries at the places");
  for (const LandmarkId d : dropped_)
    if (!places_of_.count(d))
      s.fail("dropped_ids", "landmark " + id(d) + " is dropped but at no place");
  if (dropped_.size() > options_.remember_dropped)
    s.fail("dropped_ids", std::to_string(dropped_.size()) +
                              " dropped landmarks on record, more than remember_dropped = " +
                              std::to_string(options_.remember_dropped));
}

}  // namespace budget_slam::reducers
