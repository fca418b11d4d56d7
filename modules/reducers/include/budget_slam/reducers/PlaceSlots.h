#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/session/SessionSection.h"

namespace budget_slam::reducers {

/// The places a reducer remembers, each in a slot (an index into the reducer's own per-place
/// records), at most `max_places` of them: beyond, the place visited longest ago is forgotten
/// first. Memory: O(places), bounded by the area visited and max_places, not by the run's length.
class PlaceSlots {
 public:
  explicit PlaceSlots(std::size_t max_places) : max_places_(max_places) {}

  /// The slot of place `key` visited at `step` (a new slot for a new place, reusing a freed
  /// one first: `slots()` tells how many the records must hold). Over max_places, `forget` is
  /// called for each slot that goes (never the one visited), before its slot is freed.
  std::uint32_t visit(const PlaceKey& key, StepIndex step,
                      const std::function<void(std::uint32_t)>& forget);
  /// The slot of `key`, if remembered.
  std::optional<std::uint32_t> find(const PlaceKey& key) const;
  /// Places remembered.
  std::size_t size() const { return slot_of_key_.size(); }
  /// Slots handed out so far (used or free): the size the per-slot records need.
  std::size_t slots() const { return keys_.size(); }
  bool used(std::uint32_t slot) const { return slot < used_.size() && used_[slot]; }

  /// Writes every slot (key, last visit, in use) and the free list into `s` (fields `slot_*`,
  /// `free_slots`), so that restore() gives back the same slot numbers.
  void save(session::SessionSection& s) const;
  /// The same back; InputError naming the field on a value out of range.
  void restore(const session::SessionSection& s);

 private:
  std::size_t max_places_;
  std::vector<PlaceKey> keys_;
  std::vector<StepIndex> last_visit_;
  std::vector<bool> used_;
  std::vector<std::uint32_t> free_;
  std::unordered_map<PlaceKey, std::uint32_t, PlaceKeyHash> slot_of_key_;
  std::set<std::pair<StepIndex, std::uint32_t>> by_visit_;  ///< (last visit, slot), oldest first
};

}  // namespace budget_slam::reducers
