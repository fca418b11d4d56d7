// The given keys of summary.json (docs/OUTPUTS.md "summary.json"), written and read back.
#include "GivenJson.h"

#include <cmath>

namespace budget_slam::runs {
namespace {

/// A metric that may be undefined (NaN: nothing to compare) is null in the file.
nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

nlohmann::json referenceMetricsJson(const metrics::ReferenceMetrics& m) {
  return {{"poses", m.poses},
          {"landmarks", m.landmarks},
          {"ate_m", finiteOrNull(m.ate)},
          {"ale_m", finiteOrNull(m.ale)},
          {"are_deg", finiteOrNull(m.are_deg)},
          {"ud_pct", finiteOrNull(m.ud_percent)},
          {"ud_std_factor", finiteOrNull(m.ud_std_factor)},
          {"eig_min", finiteOrNull(m.eig_min)},
          {"eig_max", finiteOrNull(m.eig_max)},
          {"eig_rows", m.eig_rows}};
}

nlohmann::json wakeUpJson(const ResumeWakeUp& w) {
  nlohmann::json j = {{"status", w.status},  {"reason", w.reason},       {"by_ids", w.by_ids},
                      {"steps", w.steps},    {"landmarks", w.landmarks}, {"inliers", w.inliers},
                      {"time_ms", w.time_ms}};
  if (w.pose) j["pose"] = *w.pose;
  return j;
}

/// `field` into `j[key]` when set.
template <class T>
void put(nlohmann::json& j, const char* key, const std::optional<T>& field) {
  if (field) j[key] = *field;
}

/// `j[key]` when it holds a value of T's JSON type.
template <class T>
void get(const nlohmann::json& j, const char* key, std::optional<T>& field) {
  if (!j.contains(key)) return;
  const auto& v = j[key];
  if constexpr (std::is_same_v<T, std::string>) {
    if (v.is_string()) field = v.get<std::string>();
  } else if constexpr (std::is_same_v<T, bool>) {
    if (v.is_boolean()) field = v.get<bool>();
  } else {
    if (v.is_number_unsigned()) field = v.get<T>();
  }
}

}  // namespace

void addGivenJson(nlohmann::json& j, const RunGiven& g) {
  put(j, "command", g.command);
  put(j, "rawlog", g.rawlog);
  put(j, "sidecar_ini", g.sidecar_ini);
  put(j, "config", g.config);
  put(j, "started", g.started);
  put(j, "earlier_run_moved_to", g.earlier_run_moved_to);
  put(j, "resumed_from", g.resumed_from);
  if (g.wake_up) j["wake_up"] = wakeUpJson(*g.wake_up);
  if (const auto& s = g.session_state) {
    j["session_state"] = {{"written", s->written}};
    if (!s->written) j["session_state"]["why"] = s->why;
  }
  put(j, "run", g.run);
  if (g.reference_metrics) j["reference_metrics"] = referenceMetricsJson(*g.reference_metrics);
  put(j, "runs", g.runs);
  put(j, "seeds", g.seeds);
  put(j, "steps", g.steps);
  put(j, "threads", g.threads);
  put(j, "map", g.map);
  put(j, "map_status", g.map_status);
}

RunGiven readGiven(const nlohmann::json& j) {
  RunGiven g;
  get(j, "command", g.command);
  get(j, "rawlog", g.rawlog);
  get(j, "sidecar_ini", g.sidecar_ini);
  get(j, "config", g.config);
  get(j, "started", g.started);
  get(j, "earlier_run_moved_to", g.earlier_run_moved_to);
  get(j, "resumed_from", g.resumed_from);
  if (j.contains("session_state") && j["session_state"].is_object()) {
    const auto& s = j["session_state"];
    SessionStateWritten w;
    w.written = s.contains("written") && s["written"].is_boolean() && s["written"].get<bool>();
    if (s.contains("why") && s["why"].is_string()) w.why = s["why"].get<std::string>();
    g.session_state = w;
  }
  get(j, "run", g.run);
  get(j, "runs", g.runs);
  if (j.contains("seeds") && j["seeds"].is_array()) {
    std::vector<std::uint64_t> seeds;
    for (const auto& s : j["seeds"])
      if (s.is_number_unsigned()) seeds.push_back(s.get<std::uint64_t>());
    g.seeds = seeds;
  }
  get(j, "steps", g.steps);
  get(j, "threads", g.threads);
  get(j, "map", g.map);
  get(j, "map_status", g.map_status);
  return g;
}

}  // namespace budget_slam::runs
