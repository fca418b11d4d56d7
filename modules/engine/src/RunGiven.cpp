#include "budget_slam/engine/RunGiven.h"

namespace budget_slam::runs {
namespace {

template <class T>
void take(std::optional<T>& field, const std::optional<T>& over) {
  if (over) field = over;
}

}  // namespace

void RunGiven::update(const RunGiven& o) {
  take(command, o.command), take(rawlog, o.rawlog), take(sidecar_ini, o.sidecar_ini);
  take(config, o.config), take(started, o.started);
  take(earlier_run_moved_to, o.earlier_run_moved_to), take(resumed_from, o.resumed_from);
  take(wake_up, o.wake_up), take(session_state, o.session_state), take(run, o.run);
  take(reference_metrics, o.reference_metrics), take(runs, o.runs), take(seeds, o.seeds);
  take(steps, o.steps), take(threads, o.threads), take(map, o.map), take(map_status, o.map_status);
}

}  // namespace budget_slam::runs
