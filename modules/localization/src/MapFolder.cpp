#include "budget_slam/localization/MapFolder.h"

#include <filesystem>

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/report/RunFileReaders.h"

namespace fs = std::filesystem;

namespace budget_slam::runs {

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
  const runs::SummaryFile read = runs::readSummary(summary);
  m.status = read.status_text;
  if (read.outcome.ground_truth) m.alignment = read.outcome.ground_truth->alignment;
  return m;
}

}  // namespace budget_slam::runs
