#include "budget_slam/reducers/BuiltinReducers.h"

#include "budget_slam/reducers/BaselineReducers.h"
#include "budget_slam/reducers/HindsightReducer.h"
#include "budget_slam/reducers/KnownSetReducer.h"
#include "budget_slam/reducers/LocalizationInformationReducer.h"
#include "budget_slam/reducers/MutualInformationReducer.h"
#include "budget_slam/reducers/PlaceCoverageReducer.h"
#include "budget_slam/reducers/ViewClusterReducers.h"

namespace budget_slam::reducers {
namespace {

/// An instrument of the benchmark's bounds: listed with role "bound", no candidate of it.
ReducerEntry bound(ReducerEntry e) {
  e.role = ReducerRole::Bound;
  return e;
}

ReducerRegistry makeRegistry() {
  ReducerRegistry r;
  r.add({"none",
         "no reducer: the map grows without a cap (the reference run)",
         {},
         [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
           return std::unique_ptr<Reducer>();
         },
         ReducerRole::Reference});
  // One line a reducer:
  r.add(RandomReducer::entry());
  r.add(OldestReducer::entry());
  r.add(InfoContentReducer::entry());
  r.add(MutualInformationReducer::entry());
  r.add(ViewClusterReducer::entry());
  r.add(ViewClusterGainReducer::entry());
  r.add(PlaceCoverageReducer::entry());
  r.add(LocalizationInformationReducer::entry());
  // Instruments of the benchmark's bounds (docs/EXPERIMENTS.md "Bounds"), not rules:
  r.add(bound(HindsightReducer::entry()));
  r.add(bound(KnownSetReducer::entry()));
  return r;
}

ReducerRegistry& registry() {
  static ReducerRegistry r = makeRegistry();
  return r;
}

}  // namespace

const ReducerRegistry& builtinReducers() { return registry(); }

bool addReducer(ReducerEntry entry) {
  registry().add(std::move(entry));
  return true;
}

}  // namespace budget_slam::reducers
