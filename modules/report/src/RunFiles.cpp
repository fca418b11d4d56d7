#include "budget_slam/report/RunFiles.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/report/CsvWriter.h"

namespace budget_slam::report {

void writeTrajectoryTum(const std::string& path, const std::vector<TrajectoryPoint>& trajectory) {
  std::string text;
  for (const auto& p : trajectory) {
    if (!std::isfinite(p.t) || !std::isfinite(p.pose.x) || !std::isfinite(p.pose.y) ||
        !std::isfinite(p.pose.phi))
      throw Error("cannot write '" + path + "': the pose of step " + std::to_string(p.step) +
                  " is not finite");
    // Rotation by yaw about z: q = (0, 0, sin(yaw/2), cos(yaw/2)).
    const double h = 0.5 * p.pose.phi;
    text += formatDouble(p.t) + ' ' + formatDouble(p.pose.x) + ' ' + formatDouble(p.pose.y) +
            " 0 0 0 " + formatDouble(std::sin(h)) + ' ' + formatDouble(std::cos(h)) + '\n';
  }
  writeFileAtomically(path, text);
}

void writeLandmarksCsv(const std::string& path, const std::vector<LandmarkView>& landmarks,
                       const std::vector<LandmarkConfirmation>& confirmations) {
  if (!confirmations.empty() && confirmations.size() != landmarks.size())
    throw std::logic_error("writeLandmarksCsv: one confirmation a landmark");
  CsvWriter csv(path,
                {"id", "x", "y", "cov_xx", "cov_xy", "cov_yy", "n_obs", "obs_mean_x", "obs_mean_y",
                 "first_step", "last_step", "last_confirmed_step", "misses"},
                CsvWriter::Mode::WholeFile);
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const LandmarkView& l = landmarks[i];
    const LandmarkConfirmation c =
        confirmations.empty() ? LandmarkConfirmation{l.last_step, 0} : confirmations[i];
    if (!l.mean.allFinite() || !l.cov.allFinite() || !l.obs_mean.allFinite())
      throw Error("cannot write '" + path + "': landmark " + std::to_string(l.id) +
                  " has a non-finite estimate");
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
        .cell(l.last_step)
        .cell(c.last_confirmed_step)
        .cell(c.misses);
    csv.endRow();
  }
  csv.close();
}

void writeJson(const std::string& path, const nlohmann::json& j) {
  // Strings that are not UTF-8 (an error text echoing corrupt file bytes) would make dump() throw:
  // their bad bytes become U+FFFD instead, so summary.json is always written and always valid.
  writeFileAtomically(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + '\n');
}

void writeSummaryJson(const std::string& path, const nlohmann::json& summary) {
  try {
    writeJson(path, summary);
  } catch (const Error& e) {
    // The short form: a few hundred bytes, whatever the run was.
    constexpr std::size_t kMaxError = 1000;
    nlohmann::json cut = nlohmann::json::object();
    for (const char* key :
         {"status", "error", "started", "command", "files_not_written", "earlier_run_moved_to"})
      if (summary.contains(key)) cut[key] = summary[key];
    if (cut.contains("error") && cut["error"].is_string() &&
        cut["error"].get<std::string>().size() > kMaxError)
      cut["error"] = cut["error"].get<std::string>().substr(0, kMaxError) + "...";
    cut["summary_cut"] = std::string("the whole summary could not be written: ") + e.what();
    writeJson(path, cut);
  }
}

std::string outputFailureLine(const std::exception& e) { return failureLine(e); }

const std::vector<std::string>& stepsCsvColumns() {
  static const std::vector<std::string> c = {"step",
                                             "t",
                                             "n_landmarks",
                                             "n_new",
                                             "n_dropped",
                                             "n_poses",
                                             "x",
                                             "y",
                                             "yaw",
                                             "var_x",
                                             "var_y",
                                             "var_yaw",
                                             "step_ms",
                                             "step_cpu_ms",
                                             "rss_bytes",
                                             "reloc_landmarks",
                                             "reloc_coverage_so_far_pct",
                                             "n_refused"};
  return c;
}

const std::vector<std::string>& evictionsCsvColumns() {
  static const std::vector<std::string> c = {"step",   "landmark_id",    "reducer",
                                             "score",  "n_before",       "n_after",
                                             "reason", "shadow_choices", "shadow_errors"};
  return c;
}

}  // namespace budget_slam::report
