#include "MapFolder.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/RunFileReaders.h"

namespace fs = std::filesystem;

namespace budget_slam::app {
namespace {

/// summary.json is a few kilobytes; anything this large is not one.
constexpr std::uintmax_t kMaxSummaryBytes = 16u << 20;

double finiteField(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
    throw InputError(file + ": ground_truth.map_alignment." + key + " is not a finite number");
  return j[key].get<double>();
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
  if (fs::file_size(summary, ec) > kMaxSummaryBytes)
    throw InputError(summary + ": larger than a budget-slam summary.json");
  std::ifstream in(summary);
  if (!in) throw InputError(summary + ": cannot open (not readable)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();
    throw InputError(summary + ": not valid JSON (" + what.substr(0, what.find('\n')) + ")");
  }
  if (!j.is_object()) throw InputError(summary + ": not a budget-slam summary (not an object)");
  if (j.contains("status") && j["status"].is_string()) m.status = j["status"].get<std::string>();
  if (j.contains("ground_truth") && j["ground_truth"].is_object() &&
      j["ground_truth"].contains("map_alignment")) {
    const auto& a = j["ground_truth"]["map_alignment"];
    if (!a.is_object())
      throw InputError(summary + ": ground_truth.map_alignment is not an object");
    const std::string source = a.contains("source") && a["source"].is_string()
                                   ? a["source"].get<std::string>()
                                   : std::string("summary.json");
    const std::size_t points =
        a.contains("points") && a["points"].is_number_unsigned() ? a["points"].get<std::size_t>() : 0;
    m.alignment = metrics::MapAlignment::fromPose(finiteField(a, "x", summary),
                                                  finiteField(a, "y", summary),
                                                  finiteField(a, "yaw", summary), source, points);
  }
  return m;
}

}  // namespace budget_slam::app
