#pragma once
#include <cstdint>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "budget_slam/core/Ids.h"

namespace budget_slam::reducers {

/// The newcomers that lost their admission ([LandmarkBudget] admission = compete), so that a
/// refused landmark is not re-tried at every step it stays in view: its readings are left out
/// for `base_wait` steps after the first refusal, twice as long after the second, and so on
/// (at most 64 x base_wait). An admitted landmark is forgotten. Memory is bounded: at most
/// `capacity` ids, the one refused longest ago forgotten first (it would merely be re-tried
/// early). Cost: O(log capacity) a refusal, O(1) a look-up.
class RefusalMemory {
 public:
  RefusalMemory(std::size_t capacity, std::size_t base_wait);

  /// `id` was refused after step `step`.
  void refused(LandmarkId id, StepIndex step);
  /// `id` won its place: its refusals are forgotten.
  void admitted(LandmarkId id);
  /// True while `id`'s readings are left out at step `step`.
  bool withheld(LandmarkId id, StepIndex step) const;

  std::size_t size() const { return entries_.size(); }
  std::size_t capacity() const { return capacity_; }
  /// Refusals of `id` remembered (0 when unknown).
  std::uint32_t refusals(LandmarkId id) const;
  /// First step at which `id` may compete again (0 when unknown).
  StepIndex retryAt(LandmarkId id) const;

  /// One remembered refusal, for the session state (docs/OUTPUTS.md "Session state").
  struct Record {
    LandmarkId id = kNoLandmarkId;
    StepIndex refused_at = 0, retry_at = 0;
    std::uint32_t refusals = 0;
  };
  /// Every refusal remembered, oldest first.
  std::vector<Record> records() const;
  /// Replaces the memory by `records` (oldest first, as records() gives them); beyond capacity()
  /// the oldest are forgotten, as refused() would.
  void restore(const std::vector<Record>& records);

 private:
  struct Entry {
    StepIndex refused_at = 0;
    StepIndex retry_at = 0;
    std::uint32_t refusals = 0;
  };
  std::size_t capacity_, base_wait_;
  std::unordered_map<LandmarkId, Entry> entries_;
  std::set<std::pair<StepIndex, LandmarkId>> by_age_;  ///< (refused_at, id), oldest first
};

}  // namespace budget_slam::reducers
