#include "budget_slam/reducers/PlaceSlots.h"

#include <limits>
#include <string>

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

void PlaceSlots::save(session::SessionSection& s) const {
  std::vector<std::int64_t> ix, iy, sector, visit, used, free(free_.begin(), free_.end());
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    ix.push_back(keys_[k].ix);
    iy.push_back(keys_[k].iy);
    sector.push_back(keys_[k].sector);
    visit.push_back(static_cast<std::int64_t>(last_visit_[k]));
    used.push_back(used_[k] ? 1 : 0);
  }
  s.putIntegers("slot_ix", std::move(ix));
  s.putIntegers("slot_iy", std::move(iy));
  s.putIntegers("slot_sector", std::move(sector));
  s.putIntegers("slot_last_visit", std::move(visit));
  s.putIntegers("slot_used", std::move(used));
  s.putIntegers("free_slots", std::move(free));
}

void PlaceSlots::restore(const session::SessionSection& s) {
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  const auto& ix = s.integers("slot_ix");
  const std::size_t n = ix.size();
  const auto& iy = s.integers("slot_iy", n, -kMax, kMax);
  const auto& sector = s.integers("slot_sector", n, 0, std::numeric_limits<std::uint32_t>::max());
  const auto& visit = s.integers("slot_last_visit", n, 0, kMax);
  const auto& used = s.integers("slot_used", n, 0, 1);
  const auto& free = s.integers("free_slots");
  keys_.clear(), last_visit_.clear(), used_.clear(), free_.clear();
  slot_of_key_.clear(), by_visit_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    keys_.push_back({ix[k], iy[k], static_cast<std::uint32_t>(sector[k])});
    last_visit_.push_back(static_cast<StepIndex>(visit[k]));
    used_.push_back(used[k] != 0);
    if (!used_[k]) continue;
    if (!slot_of_key_.emplace(keys_[k], static_cast<std::uint32_t>(k)).second)
      s.fail("slot_ix", "two slots hold the same place");
    by_visit_.insert({last_visit_[k], static_cast<std::uint32_t>(k)});
  }
  for (const auto f : free) {
    if (f < 0 || static_cast<std::size_t>(f) >= n || used_[static_cast<std::size_t>(f)])
      s.fail("free_slots", "slot " + std::to_string(f) + " is not a free slot");
    free_.push_back(static_cast<std::uint32_t>(f));
  }
  if (slot_of_key_.size() > max_places_)
    s.fail("slot_used",
           std::to_string(slot_of_key_.size()) +
               " places, more than the reducer's max_places = " + std::to_string(max_places_));
}

}  // namespace budget_slam::reducers
