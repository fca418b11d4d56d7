// The typed requests of run(), compare() and localize() from their Python arguments
// (RequestArgs.h).
#include "RequestArgs.h"

#include <pybind11/stl.h>

#include <type_traits>
#include <utility>

#include "budget_slam/core/Error.h"
#include "budget_slam/runs/RequestChecks.h"

namespace py = pybind11;

namespace budget_slam::python {

namespace {

/// run()'s or compare()'s request (`command`): the same checks, in the same order and with the
/// same messages, as the command line's.
template <class Request>
Request requestOf(const char* command, const py::dict& d) {
  constexpr bool kRun = std::is_same_v<Request, runs::RunRequest>;
  const auto text = [&](const char* key) {
    return d.contains(key) && !d[key].is_none()
               ? std::optional<std::string>(py::str(d[key]).cast<std::string>())
               : std::nullopt;
  };
  Request r;
  r.common.config = text("config").value_or("");
  r.common.rawlog = text("rawlog").value_or("");
  r.common.outdir = text("outdir").value_or("");
  r.common.quiet = true;  // nothing on stdout, no progress on stderr: the callback has it
  r.common.force = d.contains("force") && d["force"].cast<bool>();
  if (d.contains("sets")) r.common.sets = d["sets"].cast<std::vector<std::string>>();
  r.backend = text("backend").value_or("");
  std::optional<std::string> reducers;
  if constexpr (kRun) {
    r.reducer = text("reducer").value_or("");
    r.resume = text("resume").value_or("");
    r.wake_up = d.contains("wake_up") && d["wake_up"].cast<bool>();
    runs::checkWakeUp(r);
  } else {
    if (d.contains("reducers") && !d["reducers"].is_none()) {
      std::string joined;
      for (const auto& n : d["reducers"].cast<std::vector<std::string>>()) {
        joined += (joined.empty() ? "" : ",") + n;
        if (!n.empty()) r.reducers.push_back(n);
      }
      reducers = joined;
    }
    if (d.contains("threads")) r.threads = static_cast<unsigned>(d["threads"].cast<long long>());
  }
  try {
    // A flag given with an empty value (the command line's refuseEmptyValues, its order).
    const std::pair<const char*, std::optional<std::string>> given[] = {
        {"config", text("config")},   {"input", text("rawlog")},    {"out", text("outdir")},
        {"reducer", text("reducer")}, {"reducers", reducers},       {"seeds", text("seeds")},
        {"cap", text("cap")},         {"backend", text("backend")}, {"resume", text("resume")}};
    for (const auto& [flag, value] : given) runs::refuseEmptyValue(flag, value);
    if (const auto v = text("max_steps")) r.common.max_steps = runs::parseMaxSteps(*v);
    if constexpr (kRun) {
      if (const auto v = text("skip_steps")) r.skip_steps = runs::parseSkipSteps(*v);
    } else {
      if (const auto v = text("seeds")) r.seeds = runs::parseSeeds(*v);
    }
    if (const auto v = text("cap")) r.cap = runs::parseCap(*v);
    runs::checkRequest(r);
  } catch (const ConfigError& e) {
    throw runs::withHelpHint(command, e);
  }
  return r;
}

}  // namespace

runs::RunRequest runRequestOf(const py::dict& d) { return requestOf<runs::RunRequest>("run", d); }

runs::CompareRequest compareRequestOf(const py::dict& d) {
  return requestOf<runs::CompareRequest>("compare", d);
}

runs::LocalizeRequest localizeRequestOf(const std::optional<std::string>& config,
                                        const std::optional<std::string>& rawlog,
                                        const std::string& map, const std::string& outdir,
                                        const std::vector<std::string>& sets,
                                        const std::optional<std::string>& start_pose, bool wake_up,
                                        const std::optional<std::string>& reference_trajectory,
                                        const std::optional<std::string>& max_steps, bool force) {
  runs::LocalizeRequest r;
  r.common.config = config.value_or("");
  r.map_dir = map;
  r.common.rawlog = rawlog.value_or("");
  r.common.outdir = outdir;
  r.common.sets = sets;
  r.start_pose = start_pose;
  r.wake_up = wake_up;
  r.reference_trajectory = reference_trajectory.value_or("");
  r.common.force = force;
  r.common.quiet = true;
  try {
    runs::checkRequest(r);
    // A value given empty is refused, as the command line refuses `--map ''`.
    for (const auto& [flag, value] :
         {std::pair<const char*, std::optional<std::string>>{"config", config},
          {"map", map},
          {"input", rawlog},
          {"out", outdir},
          {"reference-trajectory", reference_trajectory}})
      runs::refuseEmptyValue(flag, value);
    if (max_steps) r.common.max_steps = runs::parseMaxSteps(*max_steps);
  } catch (const ConfigError& e) {
    throw runs::withHelpHint("localize", e);
  }
  return r;
}

}  // namespace budget_slam::python
