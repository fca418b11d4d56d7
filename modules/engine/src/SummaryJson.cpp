#include "budget_slam/engine/SummaryJson.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "GivenJson.h"
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

nlohmann::json poseJson(const Pose2& p) { return {{"x", p.x}, {"y", p.y}, {"yaw", p.phi}}; }

/// A localization's start_pose, counts, localization and timings blocks into `j`.
void addLocalizationJson(nlohmann::json& j, const LocalizationOutcome& o) {
  j["start_pose"] = poseJson(o.start.pose.mean);
  j["start_pose"]["source"] = o.start.source;
  j["counts"] = {{"steps", o.counts.steps}, {"map_landmarks", o.counts.map_landmarks}};
  const auto& m = o.localization;
  const auto& s = m.score;
  const auto number = report::jsonNumber;
  j["localization"] = {
      {"min_landmarks", m.min_landmarks},
      {"lost_threshold_m", m.lost_threshold_m},
      {"error_against",
       m.error_against.empty() ? nlohmann::json() : nlohmann::json(m.error_against)},
      {"error_file", m.error_file},
      {"success_xy_m", m.success_xy_m},
      {"success_yaw_deg", m.success_yaw_deg},
      {"place_size_m", m.place_size_m},
      {"heading_sectors", m.heading_sectors},
      {"mapped_area", m.mapped_everywhere
                          ? "everywhere (no mapping path)"
                          : "cells of " + std::to_string(m.mapped_cell_m) + " m within " +
                                std::to_string(m.mapped_reach_m) + " m of the mapping path"},
      {"rmse_m", number(s.rmse_m)},
      {"max_m", number(s.max_m)},
      {"lost_pct", number(s.lost_pct)},
      {"steps_compared", s.compared},
      {"steps_scored", s.scored},
      {"scored_pct", number(s.scored_pct)},
      {"steps_lost", s.lost},
      {"success_per_place_pct", number(s.success_pct)},
      {"places", s.places},
      {"coverage_pct", number(s.coverage_pct)},
      {"mean_landmarks", number(s.mean_landmarks)},
      {"nees_mean", number(s.nees_mean)},
      {"nees_samples", s.nees_samples},
      {"readings_used", m.readings_used},
      {"readings_gated", m.readings_gated},
      {"recoveries", m.recoveries},
      {"readings_not_in_map", m.readings_not_in_map},
      {"readings_consistent_with_map", m.readings_consistent_with_map},
      {"diverged_at_step",
       m.diverged_at_step ? nlohmann::json(*m.diverged_at_step) : nlohmann::json()},
      {"diverged_why", m.diverged_why}};
  j["timings"] = {{"steps_s", o.timings.steps_s}, {"step_ms_mean", number(o.timings.step_ms_mean)}};
}

/// summary.json "wake_up" of localize (docs/OUTPUTS.md "localize --wake-up").
nlohmann::json wakeUpJson(const LocalizationWakeUp& w) {
  const auto& r = w.result;
  nlohmann::json j = {{"requested", w.asked ? "--wake-up" : "no start pose"},
                      {"found", w.found()},
                      {"status", wakeup::statusName(r.status)},
                      {"reason", wakeup::reasonName(r.reason)},
                      {"why_not_found", w.why_not_found},
                      {"correspondence", r.by_ids ? "ids" : "search"},
                      {"max_steps", w.max_steps},
                      {"steps_used", w.steps_used},
                      {"time_ms", w.time_ms},
                      {"readings", r.readings},
                      {"landmarks", r.landmarks},
                      {"inliers", r.inliers},
                      {"hypotheses", r.hypotheses},
                      {"runner_up_landmarks", r.runner_up},
                      {"score", r.score},
                      {"runner_up_score", r.runner_up_score},
                      {"step", nullptr},
                      {"pose", nullptr},
                      {"cov", nullptr},
                      {"error", nullptr}};
  if (w.found()) {
    j["step"] = r.step;
    j["pose"] = poseJson(r.pose.mean);
    nlohmann::json cov = nlohmann::json::array();
    for (int i = 0; i < 3; ++i)
      cov.push_back({r.pose.cov(i, 0), r.pose.cov(i, 1), r.pose.cov(i, 2)});
    j["cov"] = cov;
  }
  if (w.error)
    j["error"] = {{"against", w.error->against},
                  {"xy_m", w.error->xy_m},
                  {"yaw_deg", w.error->yaw_deg},
                  {"within_success", w.error->within_success}};
  return j;
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
  if (o.localization) addLocalizationJson(j, *o.localization);
  if (o.wake_up) j["wake_up"] = wakeUpJson(*o.wake_up);
  addGivenJson(j, o.given);
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
  o.given = readGiven(j);
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
