#pragma once
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/PlaceSlots.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// [PlaceCoverageReducer]: the places of `place-coverage` and how many landmarks each should keep
/// (docs/ALGORITHMS.md "place-coverage").
struct PlaceCoverageOptions : public TabledOptions<PlaceCoverageOptions> {
  static constexpr const char* kSection = "PlaceCoverageReducer";

  std::size_t min_landmarks = 2;  ///< k: landmarks a place should keep, >= 1 [landmarks]
  /// Side of a place's grid cell [m]; 0 = a quarter of the sensor's maximum range as the rawlog
  /// states it (1 m when it does not). >= 0.
  double place_size = 0;
  /// Heading sectors a cell is split into (a place is a cell and a sector); 0 = from the
  /// sensor's field of view: 1 for 360 deg, else round(720 deg / fov) (4 for 180 deg).
  std::size_t heading_sectors = 0;
  /// Candidates whose coverage loss is within this many places of the least loss are near-ties,
  /// decided by `tie_break` [places], >= 0.
  double near_tie = 0;
  /// How (near-)ties of coverage loss are decided (docs/ALGORITHMS.md "place-coverage").
  enum class TieBreak {
    InformationGain,  ///< the lowest information gain goes (bits)
    Spread            ///< the landmark nearest to another one of the map goes (most crowded)
  };
  TieBreak tie_break = TieBreak::InformationGain;
  /// Places remembered at most; beyond, the place visited longest ago is forgotten [places].
  std::size_t max_places = 100000;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<PlaceCoverageOptions>& table();
};

/// `place-coverage`: keeps, for every place the robot has visited, at least k landmarks it
/// observed from there, and drops the landmark whose loss least reduces that coverage.
///
/// A place is a cell of a square grid in the estimate's frame and a sector of robot heading (a
/// 180 deg sensor sees different landmarks facing north or south). Each place holds the map's
/// landmarks observed from it. The coverage of a map K is f(K) = sum over places p of
/// min(k, |K observed from p|), a monotone submodular function (a sum of concave functions of
/// counts), so dropping L costs
///   loss(L) = number of places observing L that hold at most k landmarks,
/// and the loss of a landmark can only grow as others go. The reducer keeps every loss exact by
/// updating it only where a place's count crosses k (the incremental form of lazy greedy: nothing
/// is re-evaluated that cannot have changed). It drops the candidate with the least loss; the
/// candidates within `near_tie` of it are decided by `tie_break`: the lowest information gain
/// (Backend::informationGain, bits), or the least distance to the nearest other landmark of the
/// map (spread, then the second nearest), then the lowest id. Score: the loss [places].
///
/// Memory: O(places + sightings of kept landmarks by place), bounded by the area visited (and by
/// max_places), not by the length of the run; a landmark that leaves the map is forgotten.
class PlaceCoverageReducer : public Reducer,
                             public ObservationKeeper,
                             public session::SessionStateOwner {
 public:
  explicit PlaceCoverageReducer(const PlaceCoverageOptions& options)
      : options_(options), slots_(options.max_places) {}
  static constexpr const char* kName = "place-coverage";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  void observe(const StepObservation& seen) override;
  void forget(LandmarkId id) override;
  static ReducerRegistry::Entry entry();
  /// Section `reducer.place-coverage`: the grid, the place slots, what each place saw, the
  /// landmarks' losses.
  void saveSession(session::SessionState& state) const override;
  void restoreSession(const session::SessionState& state) override;

  /// The place of a robot pose (after the first observe() has fixed size and sectors; a 1 m
  /// cell and one sector before).
  PlaceKey placeOf(const Pose2& robot) const;

  /// Coverage loss of dropping `id` now [places] (0 for a landmark never observed).
  double loss(LandmarkId id) const;
  /// f(K) of the landmarks the reducer knows (the map): sum over places of min(k, count).
  double coverage() const;
  std::size_t placeCount() const { return slots_.size(); }
  /// Landmarks of the map observed from the place of `robot` (sorted ids).
  std::vector<LandmarkId> observedFrom(const Pose2& robot) const;
  /// For every place remembered, the landmarks observed from it (sorted ids), in slot order.
  std::vector<std::vector<LandmarkId>> placeSightings() const;
  double placeSize() const { return grid_ ? grid_->size() : 0.0; }
  std::size_t headingSectors() const { return grid_ ? grid_->sectors() : 0; }

 private:
  struct Place {
    std::vector<LandmarkId> seen;  ///< map landmarks observed from here, sorted
  };
  struct Track {
    std::vector<std::uint32_t> places;  ///< slots of the places observing it
    double loss = 0;                    ///< places among them holding <= k landmarks
  };

  void addSighting(std::uint32_t slot, LandmarkId id);
  /// Takes `id` out of place `slot` (not out of the track's list), updating the losses.
  void removeFromPlace(std::uint32_t slot, LandmarkId id);
  void forgetPlace(std::uint32_t slot);

  PlaceCoverageOptions options_;
  std::optional<PlaceGrid> grid_;  ///< fixed at the first observe()
  PlaceSlots slots_;
  std::vector<Place> places_;  ///< by slot
  std::unordered_map<LandmarkId, Track> tracks_;
};

}  // namespace budget_slam::reducers
