#include "budget_slam/runs/SummaryJson.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/report/RunFiles.h"
#include "budget_slam/report/RunSummaryJson.h"

namespace fs = std::filesystem;

namespace budget_slam::runs {
namespace {

/// summary.json is a few kilobytes; anything this large is not one.
constexpr std::uintmax_t kMaxSummaryBytes = 1u << 20;
/// budget-slam's summaries nest 3 deep; JSON nested deeper than this is not one.
constexpr int kMaxSummaryDepth = 16;

nlohmann::json countsJson(const RunCounts& c) {
  return {{"steps", c.steps},
          {"landmarks_final", c.landmarks_final},
          {"landmarks_not_finite", c.landmarks_not_finite},
          {"poses_not_finite", c.poses_not_finite},
          {"landmarks_peak", c.landmarks_peak},
          {"landmarks_added", c.landmarks_added},
          {"evictions", c.evictions},
          {"refused", c.refused},
          {"poses_kept", c.poses_kept},
          {"poses_marginalized", c.poses_marginalized}};
}

nlohmann::json timingsJson(const RunTimings& t) {
  return {{"steps_s", t.steps_s},
          {"step_ms_mean", report::jsonNumber(t.step_ms_mean)},
          {"step_ms_max", t.step_ms_max},
          {"peak_rss_bytes", t.peak_rss_bytes}};
}

// Reading: lenient for what only informs (a missing or mistyped number is NaN or 0), strict for
// what a later command acts on (map_alignment, where localize starts the robot).

double number(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number())
    return std::numeric_limits<double>::quiet_NaN();
  return j[key].get<double>();
}

std::size_t count(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number_unsigned()) return 0;
  return j[key].get<std::size_t>();
}

std::string text(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_string()) return "";
  return j[key].get<std::string>();
}

/// ground_truth.map_alignment.<key>: a finite number of magnitude at most `limit` (`unit`).
double boundedField(const nlohmann::json& j, const char* key, double limit, const char* unit,
                    const std::string& file) {
  const std::string name = std::string("ground_truth.map_alignment.") + key;
  if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
    throw InputError(file + ": " + name + " is not a finite number");
  const double v = j[key].get<double>();
  if (std::abs(v) > limit) {
    char line[96];
    std::snprintf(line, sizeof line, " = %g is out of range (at most %g %s either way)", v, limit,
                  unit);
    throw InputError(file + ": " + name + line);
  }
  return v;
}

metrics::MapAlignment readAlignment(const nlohmann::json& a, const std::string& file) {
  if (!a.is_object()) throw InputError(file + ": ground_truth.map_alignment is not an object");
  // What the alignment was fitted to: one of the names mapAlignment gives, or left unsaid.
  std::string source = "summary.json";
  if (a.contains("source") && a["source"].is_string()) {
    source = a["source"].get<std::string>();
    if (source != "landmarks" && source != "trajectory" && source != "start_pose")
      throw InputError(file + ": ground_truth.map_alignment.source '" + excerpt(source) +
                       "' is none of landmarks, trajectory, start_pose");
  }
  const std::size_t points =
      a.contains("points") && a["points"].is_number_unsigned() ? a["points"].get<std::size_t>() : 0;
  return metrics::MapAlignment::fromPose(boundedField(a, "x", limits::kMaxCoordinate, "m", file),
                                         boundedField(a, "y", limits::kMaxCoordinate, "m", file),
                                         boundedField(a, "yaw", limits::kMaxAngle, "rad", file),
                                         source, points);
}

GroundTruthOutcome readGroundTruth(const nlohmann::json& g) {
  GroundTruthOutcome t;
  t.landmarks_file = text(g, "landmarks_file");
  t.path_file = text(g, "path_file");
  auto& e = t.errors;
  e.poses = count(g, "poses");
  e.trajectory_rmse = number(g, "trajectory_rmse_m");
  e.trajectory_max = number(g, "trajectory_max_m");
  e.trajectory_rmse_aligned = number(g, "trajectory_rmse_aligned_m");
  e.alignment_rotation_deg = number(g, "alignment_rotation_deg");
  e.rpe.rmse = number(g, "trajectory_rpe_10m_m");
  e.rpe.max = number(g, "trajectory_rpe_10m_max_m");
  e.rpe.pairs = count(g, "rpe_pairs");
  e.landmark_rmse_aligned = number(g, "landmark_rmse_aligned_m");
  e.landmarks = count(g, "landmarks");
  e.landmark_rmse = number(g, "landmark_rmse_m");
  t.nees.mean = number(g, "nees_mean");
  t.nees.samples = count(g, "nees_samples");
  return t;
}

RelocCoverageOutcome readRelocalization(const nlohmann::json& r) {
  RelocCoverageOutcome o;
  auto& c = o.coverage;
  c.min_landmarks = count(r, "min_landmarks");
  c.coverage_pct = number(r, "coverage_pct");
  c.mean_landmarks = number(r, "mean_landmarks");
  c.steps = count(r, "steps");
  c.steps_covered = count(r, "steps_covered");
  c.sampled = r.contains("sampled") && r["sampled"].is_boolean() && r["sampled"].get<bool>();
  o.source = text(r, "source");
  for (const auto& [k, v] : r.items())
    if (k != "min_landmarks" && k != "coverage_pct" && k != "mean_landmarks" && k != "steps" &&
        k != "steps_covered" && k != "sampled" && k != "source")
      o.details[k] = v;
  return o;
}

RunOutcome::Run readRun(const nlohmann::json& j) {
  RunOutcome::Run run;
  run.backend = text(j, "backend");
  run.reducer = text(j, "reducer");
  if (j.contains("cap") && j["cap"].is_number_unsigned()) run.cap = j["cap"].get<std::size_t>();
  if (j.contains("counts") && j["counts"].is_object()) {
    const auto& c = j["counts"];
    run.counts = {count(c, "steps"),
                  count(c, "landmarks_final"),
                  count(c, "landmarks_not_finite"),
                  count(c, "poses_not_finite"),
                  count(c, "landmarks_peak"),
                  count(c, "landmarks_added"),
                  count(c, "evictions"),
                  count(c, "refused"),
                  count(c, "poses_kept"),
                  count(c, "poses_marginalized")};
  }
  if (j.contains("timings") && j["timings"].is_object()) {
    const auto& t = j["timings"];
    run.timings = {number(t, "steps_s"), number(t, "step_ms_mean"), number(t, "step_ms_max"),
                   count(t, "peak_rss_bytes")};
  }
  if (j.contains("agreement")) run.agreement = j["agreement"];
  if (j.contains("shadow_failures")) run.shadow_failures = j["shadow_failures"];
  if (j.contains("relocalization") && j["relocalization"].is_object())
    run.relocalization = readRelocalization(j["relocalization"]);
  return run;
}

/// The keys a run driver's summary has beyond status and error (summaryJson's run blocks).
const std::vector<std::string>& runKeys() {
  static const std::vector<std::string> k = {"backend",         "reducer",       "cap",
                                             "counts",          "timings",       "agreement",
                                             "shadow_failures", "relocalization"};
  return k;
}

}  // namespace

nlohmann::json summaryJson(const RunOutcome& o) {
  nlohmann::json j;
  j["status"] = statusName(o.status);
  j["error"] = o.error;
  if (!o.files_not_written.empty()) j["files_not_written"] = o.files_not_written;
  if (o.run) {
    const auto& r = *o.run;
    j["backend"] = r.backend;
    j["reducer"] = r.reducer;
    j["cap"] = r.cap ? nlohmann::json(*r.cap) : nlohmann::json();
    j["counts"] = countsJson(r.counts);
    j["timings"] = timingsJson(r.timings);
    j["agreement"] = r.agreement;
    j["shadow_failures"] = r.shadow_failures;
  }
  if (o.ground_truth) {
    dataset::GroundTruth files;  // groundTruthJson reads the file names only
    files.landmarks_file = o.ground_truth->landmarks_file;
    files.path_file = o.ground_truth->path_file;
    j["ground_truth"] = report::groundTruthJson(files, o.ground_truth->errors, o.ground_truth->nees,
                                                o.ground_truth->alignment);
  }
  if (o.run)
    j["relocalization"] =
        report::relocalizationJson(o.run->relocalization.coverage, o.run->relocalization.source,
                                   o.run->relocalization.details);
  for (const auto& [k, v] : o.given.items()) j[k] = v;
  return j;
}

void writeSummary(const std::string& path, const RunOutcome& o) {
  report::writeSummaryJson(path, summaryJson(o));
}

const std::vector<std::string>& summaryKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k = {"status", "error", "files_not_written", "ground_truth"};
    k.insert(k.end(), runKeys().begin(), runKeys().end());
    return k;
  }();
  return keys;
}

SummaryFile summaryFromJson(nlohmann::json j, const std::string& label) {
  if (!j.is_object()) throw InputError(label + ": not a budget-slam summary (not an object)");
  SummaryFile f;
  RunOutcome& o = f.outcome;
  // A status that is none of RunStatus's words (or none at all) is not an ok run.
  o.status = RunStatus::Failed, o.kind = ErrorKind::Input;
  if (j.contains("status") && j["status"].is_string()) {
    f.status_text = excerpt(j["status"].get<std::string>());
    if (const auto s = parseStatus(j["status"].get<std::string>()))
      o.status = *s, o.kind = *s == RunStatus::Interrupted ? ErrorKind::Stopped
                              : *s == RunStatus::Ok        ? ErrorKind::None
                                                           : ErrorKind::Internal;
  }
  o.error = text(j, "error");
  if (j.contains("ground_truth") && j["ground_truth"].is_object()) {
    const auto& g = j["ground_truth"];
    o.ground_truth = readGroundTruth(g);
    if (g.contains("map_alignment"))
      o.ground_truth->alignment = readAlignment(g["map_alignment"], label);
  }
  if (j.contains("counts")) o.run = readRun(j);
  if (j.contains("files_not_written") && j["files_not_written"].is_array())
    for (const auto& n : j["files_not_written"])
      if (n.is_string()) o.files_not_written.push_back(n.get<std::string>());
  const auto& known = summaryKeys();
  for (const auto& [k, v] : j.items())
    if (std::find(known.begin(), known.end(), k) == known.end()) o.given[k] = v;
  f.json = std::move(j);
  return f;
}

SummaryFile readSummary(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  if (fs::file_size(path, ec) > kMaxSummaryBytes)
    throw InputError(path + ": larger than a budget-slam summary.json");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open (not readable)");
  nlohmann::json j;
  const nlohmann::json::parser_callback_t shallow = [&](int depth, nlohmann::json::parse_event_t,
                                                        nlohmann::json&) {
    if (depth > kMaxSummaryDepth)
      throw InputError(path + ": nested deeper than " + std::to_string(kMaxSummaryDepth) +
                       " levels, not a budget-slam summary");
    return true;
  };
  try {
    j = nlohmann::json::parse(in, shallow);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not valid JSON (" + exceptionLine(e) + ")");
  }
  return summaryFromJson(std::move(j), path);
}

}  // namespace budget_slam::runs
