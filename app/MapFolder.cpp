#include "MapFolder.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/report/RunFileReaders.h"

namespace fs = std::filesystem;

namespace budget_slam::app {
namespace {

/// summary.json is a few kilobytes; anything this large is not one.
constexpr std::uintmax_t kMaxSummaryBytes = 1u << 20;
/// budget-slam's summaries nest 3 deep; JSON nested deeper than this is not one.
constexpr int kMaxSummaryDepth = 16;

/// ground_truth.map_alignment.<key>: a finite number of magnitude at most `limit` (`unit`).
double boundedField(const nlohmann::json& j, const char* key, double limit, const char* unit,
                    const std::string& file) {
  const std::string name = std::string("ground_truth.map_alignment.") + key;
  if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
    throw InputError(file + ": " + name + " is not a finite number");
  const double v = j[key].get<double>();
  if (std::abs(v) > limit) {
    char text[96];
    std::snprintf(text, sizeof text, " = %g is out of range (at most %g %s either way)", v, limit,
                  unit);
    throw InputError(file + ": " + name + text);
  }
  return v;
}

}  // namespace

MapFolder loadMapFolder(const std::string& dir, std::size_t max_landmarks,
                        std::size_t max_path_poses) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("map folder '" + dir + "': no such folder");
  MapFolder m;
  m.dir = dir;
  const std::string csv = (fs::path(dir) / "landmarks.csv").string();
  m.landmarks = report::readLandmarksCsv(csv, max_landmarks);
  const std::string tum = (fs::path(dir) / "trajectory.tum").string();
  if (fs::exists(tum, ec))
    for (const auto& p : report::readTrajectoryTum(tum, max_path_poses)) m.path.push_back(p.pose);

  const std::string summary = (fs::path(dir) / "summary.json").string();
  if (!fs::exists(summary, ec)) return m;
  if (!fs::is_regular_file(summary, ec)) throw InputError(summary + ": not a regular file");
  if (fs::file_size(summary, ec) > kMaxSummaryBytes)
    throw InputError(summary + ": larger than a budget-slam summary.json");
  std::ifstream in(summary);
  if (!in) throw InputError(summary + ": cannot open (not readable)");
  nlohmann::json j;
  const nlohmann::json::parser_callback_t shallow = [&](int depth, nlohmann::json::parse_event_t,
                                                        nlohmann::json&) {
    if (depth > kMaxSummaryDepth)
      throw InputError(summary + ": nested deeper than " + std::to_string(kMaxSummaryDepth) +
                       " levels, not a budget-slam summary");
    return true;
  };
  try {
    j = nlohmann::json::parse(in, shallow);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(summary + ": not valid JSON (" + exceptionLine(e) + ")");
  }
  if (!j.is_object()) throw InputError(summary + ": not a budget-slam summary (not an object)");
  if (j.contains("status") && j["status"].is_string())
    m.status = excerpt(j["status"].get<std::string>());
  if (j.contains("ground_truth") && j["ground_truth"].is_object() &&
      j["ground_truth"].contains("map_alignment")) {
    const auto& a = j["ground_truth"]["map_alignment"];
    if (!a.is_object()) throw InputError(summary + ": ground_truth.map_alignment is not an object");
    // What the alignment was fitted to: one of the names mapAlignment gives, or left unsaid.
    std::string source = "summary.json";
    if (a.contains("source") && a["source"].is_string()) {
      source = a["source"].get<std::string>();
      if (source != "landmarks" && source != "trajectory" && source != "start_pose")
        throw InputError(summary + ": ground_truth.map_alignment.source '" + excerpt(source) +
                         "' is none of landmarks, trajectory, start_pose");
    }
    const std::size_t points = a.contains("points") && a["points"].is_number_unsigned()
                                   ? a["points"].get<std::size_t>()
                                   : 0;
    m.alignment = metrics::MapAlignment::fromPose(
        boundedField(a, "x", limits::kMaxCoordinate, "m", summary),
        boundedField(a, "y", limits::kMaxCoordinate, "m", summary),
        boundedField(a, "yaw", limits::kMaxAngle, "rad", summary), source, points);
  }
  return m;
}

}  // namespace budget_slam::app
