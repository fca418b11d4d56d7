#pragma once
#include <set>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/ReducerRegistry.h"

namespace budget_slam::reducers {

/// [KnownSetReducer] (docs/EXPERIMENTS.md "Bounds").
struct KnownSetOptions : public TabledOptions<KnownSetOptions> {
  static constexpr const char* kSection = "KnownSetReducer";
  /// When the landmarks outside the set leave the map.
  enum class When {
    FirstSight,  ///< first_sight: after every step, so the map holds the set's landmarks seen
                 ///< so far and nothing else (a mapping run that knows its final map)
    End          ///< end: after the last step (the unreduced map cut to the set)
  };
  std::vector<std::string> ids;  ///< the landmark ids of the set (sensor IDs); none: the empty set
  When when = When::FirstSight;
  static const OptionTable<KnownSetOptions>& table();
};

/// `known-set`: not a rule but an instrument. It keeps exactly a given set of landmarks (e.g. the
/// hindsight selection of another run, `hindsight`) and drops every other landmark the map takes
/// in, on its own schedule (reason `known_set`), whatever the cap: with `first_sight` the cost
/// of mapping with the set's few landmarks is measured. A cap below the set's size still holds:
/// over it, the set's landmark with the highest id goes first.
class KnownSetReducer : public Reducer, public DropScheduler {
 public:
  explicit KnownSetReducer(const KnownSetOptions& options);
  static constexpr const char* kName = "known-set";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  ScheduledDrops scheduled(const ScheduleContext& ctx) override;
  bool decidesMapSize() const override { return true; }
  bool readmitsEvicted() const override { return true; }
  static ReducerRegistry::Entry entry();
  const std::set<LandmarkId>& set() const { return set_; }

 private:
  KnownSetOptions options_;
  std::set<LandmarkId> set_;
};

}  // namespace budget_slam::reducers
