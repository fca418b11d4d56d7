#include "budget_slam/reducers/RefusalMemory.h"

#include <algorithm>
#include <stdexcept>

namespace budget_slam::reducers {

namespace {
/// The wait doubles with each refusal up to 2^6 = 64 base waits.
constexpr std::uint32_t kMaxDoublings = 6;
}  // namespace

RefusalMemory::RefusalMemory(std::size_t capacity, std::size_t base_wait)
    : capacity_(capacity), base_wait_(base_wait) {
  if (capacity_ == 0 || base_wait_ == 0)
    throw std::invalid_argument("RefusalMemory: capacity and base wait must be at least 1");
}

void RefusalMemory::refused(LandmarkId id, StepIndex step) {
  Entry& e = entries_[id];
  if (e.refusals > 0) by_age_.erase({e.refused_at, id});
  ++e.refusals;
  e.refused_at = step;
  const std::uint32_t doublings = std::min(e.refusals - 1, kMaxDoublings);
  e.retry_at = step + 1 + base_wait_ * (std::size_t(1) << doublings);
  by_age_.insert({step, id});
  while (entries_.size() > capacity_) {
    const auto oldest = by_age_.begin();
    entries_.erase(oldest->second);
    by_age_.erase(oldest);
  }
}

void RefusalMemory::admitted(LandmarkId id) {
  const auto it = entries_.find(id);
  if (it == entries_.end()) return;
  by_age_.erase({it->second.refused_at, id});
  entries_.erase(it);
}

bool RefusalMemory::withheld(LandmarkId id, StepIndex step) const {
  const auto it = entries_.find(id);
  return it != entries_.end() && step < it->second.retry_at;
}

std::uint32_t RefusalMemory::refusals(LandmarkId id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? 0 : it->second.refusals;
}

StepIndex RefusalMemory::retryAt(LandmarkId id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? 0 : it->second.retry_at;
}

std::vector<RefusalMemory::Record> RefusalMemory::records() const {
  std::vector<Record> out;
  out.reserve(by_age_.size());
  for (const auto& [at, id] : by_age_) {
    const Entry& e = entries_.at(id);
    out.push_back({id, e.refused_at, e.retry_at, e.refusals});
  }
  return out;
}

void RefusalMemory::restore(const std::vector<Record>& records) {
  entries_.clear();
  by_age_.clear();
  for (const Record& r : records) {
    if (entries_.count(r.id)) by_age_.erase({entries_[r.id].refused_at, r.id});
    entries_[r.id] = {r.refused_at, r.retry_at, r.refusals};
    by_age_.insert({r.refused_at, r.id});
  }
  while (entries_.size() > capacity_) {
    const auto oldest = by_age_.begin();
    entries_.erase(oldest->second);
    by_age_.erase(oldest);
  }
}

}  // namespace budget_slam::reducers
