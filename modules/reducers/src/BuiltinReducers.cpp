#include "budget_slam/reducers/BuiltinReducers.h"

#include "budget_slam/reducers/BaselineReducers.h"

namespace budget_slam::reducers {
namespace {

ReducerRegistry makeRegistry() {
  ReducerRegistry r;
  r.add({"none",
         "no reducer: the map grows without a cap (the reference run)",
         "",
         {},
         [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
           return std::unique_ptr<Reducer>();
         }});
  // One line a reducer:
  r.add(RandomReducer::entry());
  r.add(OldestReducer::entry());
  r.add(InfoContentReducer::entry());
  return r;
}

}  // namespace

const ReducerRegistry& builtinReducers() {
  static const ReducerRegistry registry = makeRegistry();
  return registry;
}

}  // namespace budget_slam::reducers
