#include "budget_slam/reducers/PlaceCoverageReducer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

#include "ReducerSession.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::reducers {

namespace {

const EnumNames<PlaceCoverageOptions::TieBreak>& tieBreakNames() {
  using T = PlaceCoverageOptions::TieBreak;
  static const EnumNames<T> n = {{"information_gain", T::InformationGain}, {"spread", T::Spread}};
  return n;
}

/// Distances [m] from landmark `me` (an index into `map`) to its nearest and its second
/// nearest other landmark of the map (infinity when there are none).
std::pair<double, double> nearestTwoDistances(const std::vector<LandmarkView>& map,
                                              std::size_t me) {
  double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (i == me) continue;
    const double d = (map[i].mean - map[me].mean).norm();
    if (d < d1)
      d2 = d1, d1 = d;
    else if (d < d2)
      d2 = d;
  }
  return {d1, d2};
}

}  // namespace

const OptionTable<PlaceCoverageOptions>& PlaceCoverageOptions::table() {
  using O = PlaceCoverageOptions;
  static const OptionTable<O> t = {
      option::integer("min_landmarks", &O::min_landmarks, 1, 1000000, "[landmarks]"),
      option::real("place_size", &O::place_size, 0.0, 1e6, "[m], 0 = from the sensor's range"),
      option::integer("heading_sectors", &O::heading_sectors, 0, 360,
                      "0 = from the sensor's field of view"),
      option::real("near_tie", &O::near_tie, 0.0, 1e12, "[places]"),
      option::choice("tie_break", &O::tie_break, tieBreakNames()),
      option::integer("max_places", &O::max_places, 1, 100000000, "[places]"),
  };
  return t;
}

PlaceKey PlaceCoverageReducer::placeOf(const Pose2& robot) const {
  return (grid_ ? *grid_ : PlaceGrid(1.0, 1)).placeOf(robot);
}

void PlaceCoverageReducer::addSighting(std::uint32_t slot, LandmarkId id) {
  Place& p = places_[slot];
  const auto pos = std::lower_bound(p.seen.begin(), p.seen.end(), id);
  if (pos != p.seen.end() && *pos == id) return;
  const std::size_t k = options_.min_landmarks;
  const std::size_t before = p.seen.size();
  Track& t = tracks_[id];
  if (before + 1 <= k) {
    t.loss += 1;  // the place still holds at most k: losing `id` would cost it
  } else if (before == k) {
    // The place goes from k to k + 1 landmarks: none of the old ones is needed there any more.
    for (const LandmarkId other : p.seen) tracks_[other].loss -= 1;
  }
  p.seen.insert(pos, id);
  t.places.push_back(slot);
}

void PlaceCoverageReducer::removeFromPlace(std::uint32_t slot, LandmarkId id) {
  Place& p = places_[slot];
  const auto pos = std::lower_bound(p.seen.begin(), p.seen.end(), id);
  if (pos == p.seen.end() || *pos != id) return;
  const std::size_t k = options_.min_landmarks;
  const std::size_t before = p.seen.size();
  p.seen.erase(pos);
  if (before <= k) {
    tracks_[id].loss -= 1;
  } else if (before == k + 1) {
    // Down to k: every remaining landmark of the place is needed there now.
    for (const LandmarkId other : p.seen) tracks_[other].loss += 1;
  }
}

void PlaceCoverageReducer::forgetPlace(std::uint32_t slot) {
  Place& p = places_[slot];
  const bool counted = p.seen.size() <= options_.min_landmarks;
  for (const LandmarkId id : p.seen) {
    Track& t = tracks_[id];
    if (counted) t.loss -= 1;
    t.places.erase(std::find(t.places.begin(), t.places.end(), slot));
  }
  p = Place();
}

void PlaceCoverageReducer::observe(const StepObservation& seen) {
  if (!grid_)
    grid_ = PlaceGrid::fromSensor(options_.place_size, options_.heading_sectors,
                                  seen.sensor_max_range, seen.sensor_fov);
  if (seen.observed.empty()) return;  // a place with no landmark constrains no choice
  const std::uint32_t slot = slots_.visit(grid_->placeOf(seen.robot), seen.step,
                                          [this](std::uint32_t gone) { forgetPlace(gone); });
  places_.resize(slots_.slots());
  for (const LandmarkId id : seen.observed) addSighting(slot, id);
}

void PlaceCoverageReducer::forget(LandmarkId id) {
  const auto it = tracks_.find(id);
  if (it == tracks_.end()) return;
  const std::vector<std::uint32_t> slots = it->second.places;
  for (const std::uint32_t slot : slots) removeFromPlace(slot, id);
  tracks_.erase(id);
}

double PlaceCoverageReducer::loss(LandmarkId id) const {
  const auto it = tracks_.find(id);
  return it == tracks_.end() ? 0.0 : it->second.loss;
}

double PlaceCoverageReducer::coverage() const {
  double f = 0;
  for (std::uint32_t s = 0; s < places_.size(); ++s)
    if (slots_.used(s))
      f += static_cast<double>(
          std::min<std::size_t>(places_[s].seen.size(), options_.min_landmarks));
  return f;
}

std::vector<std::vector<LandmarkId>> PlaceCoverageReducer::placeSightings() const {
  std::vector<std::vector<LandmarkId>> out;
  for (std::uint32_t s = 0; s < places_.size(); ++s)
    if (slots_.used(s)) out.push_back(places_[s].seen);
  return out;
}

std::vector<LandmarkId> PlaceCoverageReducer::observedFrom(const Pose2& robot) const {
  const auto slot = slots_.find(placeOf(robot));
  return slot ? places_[*slot].seen : std::vector<LandmarkId>();
}

ReducerChoice PlaceCoverageReducer::choose(const DropContext& ctx) {
  // Least coverage loss; the candidates within near_tie of it go to the tie-break.
  double least = std::numeric_limits<double>::infinity();
  std::vector<double> losses;
  losses.reserve(ctx.candidates.size());
  for (const std::size_t i : ctx.candidates) {
    losses.push_back(loss(ctx.landmarks[i].id));
    least = std::min(least, losses.back());
  }
  std::vector<std::size_t> tied;  // indices into ctx.landmarks
  std::vector<double> tied_loss;
  for (std::size_t c = 0; c < ctx.candidates.size(); ++c)
    if (losses[c] <= least + options_.near_tie) {
      tied.push_back(ctx.candidates[c]);
      tied_loss.push_back(losses[c]);
    }
  const auto idOf = [&](std::size_t j) { return ctx.landmarks[tied[j]].id; };
  if (tied.size() == 1) return {idOf(0), tied_loss.front()};

  // The tie-break's key, least goes; equal keys go to the lowest id.
  std::vector<std::pair<double, double>> key(tied.size());
  if (options_.tie_break == PlaceCoverageOptions::TieBreak::Spread) {
    // Most crowded first: the least distance [m] to another landmark of the map, then the least
    // distance to the second nearest. Unlike information gain, this does not depend on how long
    // a landmark has been observed, so a newcomer after its one-step probation is not always the
    // one to go (docs/ALGORITHMS.md "place-coverage").
    for (std::size_t j = 0; j < tied.size(); ++j)
      key[j] = nearestTwoDistances(ctx.landmarks, tied[j]);
  } else {
    std::vector<LandmarkId> ids(tied.size());
    for (std::size_t j = 0; j < tied.size(); ++j) ids[j] = idOf(j);
    const std::vector<double> gains = ctx.backend.informationGain(ids);
    for (std::size_t j = 0; j < tied.size(); ++j) key[j] = {gains[j], 0.0};
  }
  std::size_t best = 0;
  for (std::size_t j = 1; j < tied.size(); ++j)
    if (key[j] < key[best] || (key[j] == key[best] && idOf(j) < idOf(best))) best = j;
  return {idOf(best), tied_loss[best]};
}

ReducerRegistry::Entry PlaceCoverageReducer::entry() {
  return {kName,
          "keep k landmarks observed from every visited place (grid cell and heading); drop the "
          "one whose loss uncovers fewest places, near-ties by information gain or by spread",
          {tabledSection<PlaceCoverageOptions>()},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
            PlaceCoverageOptions o;
            o.loadFromConfigFile(ini, PlaceCoverageOptions::kSection);
            return std::make_unique<PlaceCoverageReducer>(o);
          }};
}

void PlaceCoverageReducer::saveSession(session::SessionState& state) const {
  session::SessionSection& s = state.section(reducerSection(name()));
  putGrid(s, grid_);
  slots_.save(s);
  std::vector<std::vector<LandmarkId>> seen;
  for (const auto& p : places_) seen.push_back(p.seen);
  putNested(s, "place_seen", seen);
  // The tracks in id order (the map's order carries no meaning).
  std::vector<LandmarkId> ids;
  for (const auto& [id, t] : tracks_) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  std::vector<std::vector<std::uint32_t>> places;
  std::vector<double> losses;
  for (const LandmarkId id : ids) {
    places.push_back(tracks_.at(id).places);
    losses.push_back(tracks_.at(id).loss);
  }
  s.putIntegers("track_ids", std::vector<std::int64_t>(ids.begin(), ids.end()));
  putNested(s, "track_places", places);
  s.putReals("track_loss", std::move(losses));
}

void PlaceCoverageReducer::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take(reducerSection(name()));
  grid_ = readGrid(s);
  slots_.restore(s);
  constexpr std::int64_t kMaxId = std::numeric_limits<std::int64_t>::max();
  const auto seen = nested(s, "place_seen", slots_.slots(), 0, kMaxId);
  places_.assign(slots_.slots(), Place());
  for (std::size_t k = 0; k < seen.size(); ++k)
    places_[k].seen.assign(seen[k].begin(), seen[k].end());
  const auto& ids = s.integers("track_ids");
  const auto places =
      nested(s, "track_places", ids.size(), 0, static_cast<std::int64_t>(slots_.slots()) - 1);
  const auto& losses = s.reals("track_loss", ids.size());
  tracks_.clear();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (tracks_.count(ids[i]))
      s.fail("track_ids", "landmark " + std::to_string(ids[i]) + " appears twice");
    Track& t = tracks_[ids[i]];
    t.places.assign(places[i].begin(), places[i].end());
    t.loss = losses[i];
  }
  // A CRC proves the file whole, not sane: the places' landmarks and the landmarks' places must
  // name each other (forgetPlace() and forget() follow them without looking), each place's list
  // sorted (lower_bound), and each loss the count of its places at or under min_landmarks.
  std::size_t sightings = 0;
  for (std::size_t k = 0; k < places_.size(); ++k) {
    const auto& seen_k = places_[k].seen;
    if (!slots_.used(static_cast<std::uint32_t>(k)) && !seen_k.empty())
      s.fail("place_seen", "place " + std::to_string(k) + " is free but holds landmarks");
    for (std::size_t j = 1; j < seen_k.size(); ++j)
      if (!(seen_k[j - 1] < seen_k[j]))
        s.fail("place_seen",
               "the landmarks of place " + std::to_string(k) + " are not in increasing order");
    for (const LandmarkId id : seen_k)
      if (!tracks_.count(id))
        s.fail("place_seen", "place " + std::to_string(k) + " holds landmark " +
                                 std::to_string(id) + ", which has no track");
    sightings += seen_k.size();
  }
  std::size_t listed = 0;
  for (const auto& [id, t] : tracks_) {
    std::vector<std::uint32_t> sorted = t.places;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      s.fail("track_places", "landmark " + std::to_string(id) + " lists a place twice");
    double loss = 0;
    for (const std::uint32_t k : t.places) {
      const auto& seen_k = places_[k].seen;
      if (!std::binary_search(seen_k.begin(), seen_k.end(), id))
        s.fail("track_places", "landmark " + std::to_string(id) + " lists place " +
                                   std::to_string(k) + ", which does not hold it");
      if (seen_k.size() <= options_.min_landmarks) loss += 1;
    }
    if (t.loss != loss)
      s.fail("track_loss", "landmark " + std::to_string(id) + " has loss " +
                               option::numberText(t.loss) + ", its places give " +
                               option::numberText(loss));
    listed += t.places.size();
  }
  if (listed != sightings)
    s.fail("track_places", std::to_string(listed) + " places listed for the landmarks, " +
                               std::to_string(sightings) + " landmarks at the places");
}

}  // namespace budget_slam::reducers
