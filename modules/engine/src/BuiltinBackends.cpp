#include "budget_slam/engine/BuiltinBackends.h"

#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/graph/GraphBackend.h"

namespace budget_slam::runs {
namespace {

BackendRegistry makeRegistry() {
  BackendRegistry r;
  // One line a backend:
  r.add(ekf::EkfBackend::entry());
  r.add(graph::GraphBackend::entry());
  return r;
}

}  // namespace

const BackendRegistry& builtinBackends() {
  static const BackendRegistry registry = makeRegistry();
  return registry;
}

}  // namespace budget_slam::runs
