#include "budget_slam/reducers/PlaceSlots.h"

namespace budget_slam::reducers {

std::uint32_t PlaceSlots::visit(const PlaceKey& key, StepIndex step,
                                const std::function<void(std::uint32_t)>& forget) {
  std::uint32_t slot;
  const auto it = slot_of_key_.find(key);
  if (it != slot_of_key_.end()) {
    slot = it->second;
    by_visit_.erase({last_visit_[slot], slot});
  } else {
    if (!free_.empty()) {
      slot = free_.back();
      free_.pop_back();
    } else {
      slot = static_cast<std::uint32_t>(keys_.size());
      keys_.emplace_back();
      last_visit_.push_back(0);
      used_.push_back(false);
    }
    keys_[slot] = key;
    used_[slot] = true;
    slot_of_key_.emplace(key, slot);
  }
  last_visit_[slot] = step;
  by_visit_.insert({step, slot});
  while (slot_of_key_.size() > max_places_) {
    const auto oldest = by_visit_.begin();
    const std::uint32_t gone = oldest->second;
    if (gone == slot) break;  // never the place being visited
    forget(gone);
    by_visit_.erase(oldest);
    slot_of_key_.erase(keys_[gone]);
    used_[gone] = false;
    free_.push_back(gone);
  }
  return slot;
}

std::optional<std::uint32_t> PlaceSlots::find(const PlaceKey& key) const {
  const auto it = slot_of_key_.find(key);
  if (it == slot_of_key_.end()) return std::nullopt;
  return it->second;
}

}  // namespace budget_slam::reducers
