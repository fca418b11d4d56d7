#include "RunSession.h"

#include <filesystem>
#include <set>
#include <vector>

#include "budget_slam/core/Error.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::app {

std::map<std::string, std::string> resumeOptions(const mrpt::config::CConfigFileBase& ini) {
  // Per-session keys: what this session reads and writes, how long, and how it reports.
  static const std::set<std::string> kSessionSections = {"Report", "Metrics", "WakeUp"};
  static const std::set<std::string> kSessionKeys = {
      "rawlog_file", "logOutput_dir", "max_steps", "ground_truth_file", "ground_truth_file_robot",
      "save_3d_scene", "SAVE_3D_SCENES", "SAVE_LOG_FREQUENCY", "keep_history"};
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
  const std::string path =
      (std::filesystem::path(run_dir) / session::kStateFileName).string();
  session::SessionState state = session::readSessionState(path);
  if (state.header.backend != backend)
    throw ConfigError("--resume " + run_dir + ": [MappingApplication] backend = " + backend +
                      ", the saved session had " + state.header.backend);
  const auto diff = session::resumeMismatches(state.header.resume_options, options);
  if (!diff.empty())
    throw ConfigError("--resume " + run_dir + ": " + diff.front() +
                      (diff.size() > 1 ? " (and " + std::to_string(diff.size() - 1) +
                                             " more option(s) differ)"
                                       : std::string()));
  return state;
}

}  // namespace budget_slam::app
