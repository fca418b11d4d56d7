#include "budget_slam/report/RunFiles.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/CsvWriter.h"

namespace budget_slam::report {

void writeTrajectoryTum(const std::string& path, const std::vector<TrajectoryPoint>& trajectory) {
  std::ofstream out(path);
  if (!out) throw Error("cannot write '" + path + "'");
  out << std::setprecision(17);
  for (const auto& p : trajectory) {
    // Rotation by yaw about z: q = (0, 0, sin(yaw/2), cos(yaw/2)).
    const double h = 0.5 * p.pose.phi;
    out << formatDouble(p.t) << ' ' << formatDouble(p.pose.x) << ' ' << formatDouble(p.pose.y)
        << " 0 0 0 " << formatDouble(std::sin(h)) << ' ' << formatDouble(std::cos(h)) << '\n';
  }
}

void writeLandmarksCsv(const std::string& path, const std::vector<LandmarkView>& landmarks) {
  CsvWriter csv(path, {"id", "x", "y", "cov_xx", "cov_xy", "cov_yy", "n_obs", "obs_mean_x",
                       "obs_mean_y", "first_step", "last_step"});
  for (const auto& l : landmarks) {
    csv.cell(static_cast<long long>(l.id))
        .cell(l.mean.x())
        .cell(l.mean.y())
        .cell(l.cov(0, 0))
        .cell(l.cov(0, 1))
        .cell(l.cov(1, 1))
        .cell(l.n_obs)
        .cell(l.obs_mean.x())
        .cell(l.obs_mean.y())
        .cell(l.first_step)
        .cell(l.last_step);
    csv.endRow();
  }
}

void writeJson(const std::string& path, const nlohmann::json& j) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw Error("cannot write '" + path + "'");
    out << j.dump(2) << '\n';
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw Error("cannot write '" + path + "'");
}

const std::vector<std::string>& stepsCsvColumns() {
  static const std::vector<std::string> c = {
      "step", "t",     "n_landmarks", "n_new",   "n_dropped", "n_poses",     "x",        "y",
      "yaw",  "var_x", "var_y",       "var_yaw", "step_ms",   "step_cpu_ms", "rss_bytes"};
  return c;
}

const std::vector<std::string>& evictionsCsvColumns() {
  static const std::vector<std::string> c = {"step",   "landmark_id",    "reducer",
                                             "score",  "n_before",       "n_after",
                                             "reason", "shadow_choices", "shadow_errors"};
  return c;
}

}  // namespace budget_slam::report
