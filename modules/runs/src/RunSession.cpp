#include "budget_slam/runs/RunSession.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <vector>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/session/SessionStateFile.h"
#include "budget_slam/wakeup/WakeUpRun.h"

namespace budget_slam::runs {

std::map<std::string, std::string> resumeOptions(const mrpt::config::CConfigFileBase& ini) {
  // Per-session keys: what this session reads and writes, how long, and how it reports.
  static const std::set<std::string> kSessionSections = {"Report", "Metrics", "WakeUp"};
  static const std::set<std::string> kSessionKeys = {
      "rawlog_file",       "logOutput_dir",           "max_steps",
      "ground_truth_file", "ground_truth_file_robot", "save_3d_scene",
      "SAVE_3D_SCENES",    "SAVE_LOG_FREQUENCY",      "keep_history"};
  std::map<std::string, std::string> out;
  std::vector<std::string> sections;
  ini.getAllSections(sections);
  for (const auto& section : sections) {
    if (kSessionSections.count(section)) continue;
    std::vector<std::string> keys;
    ini.getAllKeys(section, keys);
    for (const auto& key : keys) {
      if (section == "MappingApplication" && kSessionKeys.count(key)) continue;
      out[section + "." + key] = ini.read_string(section, key, "");
    }
  }
  return out;
}

session::SessionState loadResumeState(const std::string& run_dir, const std::string& backend,
                                      const std::map<std::string, std::string>& options) {
  const std::string path = (std::filesystem::path(run_dir) / session::kStateFileName).string();
  session::SessionState state = session::readSessionState(path);
  if (state.header.backend != backend)
    throw ConfigError("--resume " + run_dir + ": [MappingApplication] backend = " + backend +
                      ", the saved session had " + state.header.backend);
  const auto diff = session::resumeMismatches(state.header.resume_options, options);
  if (!diff.empty())
    throw ConfigError("--resume " + run_dir + ": " + diff.front() +
                      (diff.size() > 1
                           ? " (and " + std::to_string(diff.size() - 1) + " more option(s) differ)"
                           : std::string()));
  return state;
}

WakeUpOutcome wakeUpOnMap(const RunConfig& rc, session::SessionState& state, std::size_t skip) {
  wakeup::WakeUpOptions options;
  options.loadFromConfigFile(rc.ini, wakeup::WakeUpOptions::kSection);
  // The steps after the `skip` the session leaves unread, one at a time, into the same wake-up
  // as localize's (wakeup::wakeUpOver).
  dataset::RawlogReader reader(rc.rawlog);
  // A stop request ends the reading too; wakeUpOver then throws Interrupted.
  reader.setStopCheck([] { return Cancellation::requested(); });
  for (std::size_t k = 0; k < skip && reader.next(); ++k) {
  }
  std::optional<Step> step;
  const wakeup::WakeUpRun woke = wakeup::wakeUpOver(
      state.map.landmarks,
      [&]() -> const Step* { return (step = reader.next()) ? &*step : nullptr; }, options,
      wakeup::readingNoiseOf(rc.ini));
  WakeUpOutcome out;
  out.steps = woke.steps_read;
  const double ms = woke.wall_ms;
  const wakeup::WakeUpResult& r = woke.result;
  out.found = r.status == wakeup::WakeUpStatus::Found;
  ResumeWakeUp& b = out.block;
  b.status = wakeup::statusName(r.status), b.reason = wakeup::reasonName(r.reason);
  b.by_ids = r.by_ids, b.steps = out.steps, b.landmarks = r.landmarks, b.inliers = r.inliers;
  b.time_ms = ms;
  if (!out.found) {
    out.why = std::string("the robot was not found on the saved map in ") +
              std::to_string(out.steps) + " steps (" + wakeup::statusName(r.status) +
              (r.reason == wakeup::WakeUpReason::None
                   ? ""
                   : std::string(", ") + wakeup::reasonName(r.reason)) +
              "); without --wake-up the session continues where the last one stopped";
    return out;
  }
  b.pose = {r.pose.mean.x, r.pose.mean.y, r.pose.mean.phi * 180 / M_PI};
  session::RobotBlock robot;
  robot.pose = r.pose;
  robot.cross_covariance =
      Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(2 * state.map.landmarks.size()));
  state.robot = robot;
  state.robot_start = session::RobotStart::Placed;
  return out;
}

}  // namespace budget_slam::runs
