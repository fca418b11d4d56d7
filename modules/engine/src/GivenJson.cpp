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

/// A plain given key: its summary.json name and the RunGiven field behind it. The one list both
/// addGivenJson and readGiven follow (the nested blocks and `seeds` are written and read by hand).
template <class T>
struct GivenKey {
  const char* name;
  std::optional<T> RunGiven::*field;
};
const GivenKey<std::string> kTextKeys[] = {
    {"command", &RunGiven::command},
    {"rawlog", &RunGiven::rawlog},
    {"sidecar_ini", &RunGiven::sidecar_ini},
    {"config", &RunGiven::config},
    {"earlier_run_moved_to", &RunGiven::earlier_run_moved_to},
    {"resumed_from", &RunGiven::resumed_from},
    {"run", &RunGiven::run},
    {"map", &RunGiven::map},
    {"map_status", &RunGiven::map_status}};
const GivenKey<bool> kFlagKeys[] = {{"started", &RunGiven::started}};
const GivenKey<std::size_t> kCountKeys[] = {
    {"runs", &RunGiven::runs}, {"steps", &RunGiven::steps}, {"threads", &RunGiven::threads}};

}  // namespace

void addGivenJson(nlohmann::json& j, const RunGiven& g) {
  // nlohmann::json keeps its keys sorted: the order of these calls is not the file's.
  for (const auto& k : kTextKeys) put(j, k.name, g.*k.field);
  for (const auto& k : kFlagKeys) put(j, k.name, g.*k.field);
  for (const auto& k : kCountKeys) put(j, k.name, g.*k.field);
  if (g.wake_up) j["wake_up"] = wakeUpJson(*g.wake_up);
  if (const auto& s = g.session_state) {
    j["session_state"] = {{"written", s->written}};
    if (!s->written) j["session_state"]["why"] = s->why;
  }
  if (g.reference_metrics) j["reference_metrics"] = referenceMetricsJson(*g.reference_metrics);
  put(j, "seeds", g.seeds);
}

RunGiven readGiven(const nlohmann::json& j) {
  RunGiven g;
  for (const auto& k : kTextKeys) get(j, k.name, g.*k.field);
  for (const auto& k : kFlagKeys) get(j, k.name, g.*k.field);
  for (const auto& k : kCountKeys) get(j, k.name, g.*k.field);
  if (j.contains("session_state") && j["session_state"].is_object()) {
    const auto& s = j["session_state"];
    SessionStateWritten w;
    w.written = s.contains("written") && s["written"].is_boolean() && s["written"].get<bool>();
    if (s.contains("why") && s["why"].is_string()) w.why = s["why"].get<std::string>();
    g.session_state = w;
  }
  if (j.contains("seeds") && j["seeds"].is_array()) {
    std::vector<std::uint64_t> seeds;
    for (const auto& s : j["seeds"])
      if (s.is_number_unsigned()) seeds.push_back(s.get<std::uint64_t>());
    g.seeds = seeds;
  }
  return g;
}

}  // namespace budget_slam::runs
