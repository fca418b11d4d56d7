#include "MappingOptions.h"

#include <ostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::app {

const std::vector<std::string>& MappingOptions::backends() {
  static const std::vector<std::string> b = {"ekf", "graph"};
  return b;
}

void MappingOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                        const std::string& section) {
  const IniSection s(ini, section);
  rawlog_file = s.readString("rawlog_file", rawlog_file);
  backend = s.readChoice("backend", backend, backends());
  ground_truth_file = s.readString("ground_truth_file", ground_truth_file);
  ground_truth_file_robot = s.readString("ground_truth_file_robot", ground_truth_file_robot);
  logOutput_dir = s.readString("logOutput_dir", logOutput_dir);
  max_steps = static_cast<std::size_t>(s.readInt("max_steps", 0, 0));
  keep_history = s.readBool("keep_history", keep_history);
  save_3d_scene = s.readBool("save_3d_scene", save_3d_scene);
  // kf-slam's keys; its default SAVE_3D_SCENES = true would write a scene a step of a lifelong run,
  // so budget-slam writes them only when the ini asks.
  scene_every_steps = s.readBool("SAVE_3D_SCENES", false)
                          ? static_cast<std::size_t>(s.readInt("SAVE_LOG_FREQUENCY", 1, 1))
                          : 0;
  // kf-slam's default is the 3D filter, but an ini that does not say is taken as 2D here.
  kf_implementation = s.readChoice("kf_implementation", kf_implementation,
                                   {"CRangeBearingKFSLAM2D", "CRangeBearingKFSLAM"});
  if (kf_implementation != "CRangeBearingKFSLAM2D")
    throw ConfigError("[" + section + "] kf_implementation = " + kf_implementation +
                      ": budget-slam runs the 2D filter, CRangeBearingKFSLAM2D");
}

void MappingOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "rawlog_file              = " << rawlog_file << "\n";
  out << "backend                  = " << backend << "\n";
  out << "ground_truth_file        = " << ground_truth_file << "\n";
  out << "ground_truth_file_robot  = " << ground_truth_file_robot << "\n";
  out << "logOutput_dir            = " << logOutput_dir << "\n";
  out << "max_steps                = " << max_steps << "\n";
  out << "keep_history             = " << (keep_history ? "true" : "false") << "\n";
  out << "save_3d_scene            = " << (save_3d_scene ? "true" : "false") << "\n";
  out << "3D scene every [steps]   = " << scene_every_steps << " (0: never)\n";
}

std::vector<std::string> MappingOptions::keys() {
  return {"backend", "max_steps", "keep_history", "save_3d_scene"};
}

}  // namespace budget_slam::app
