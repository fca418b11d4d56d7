#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::runs {

/// [MappingApplication]: MRPT kf-slam's application section, read the way kf-slam reads it, plus
/// budget-slam's `backend`.
struct MappingOptions : public TabledOptions<MappingOptions> {
  static constexpr const char* kSection = "MappingApplication";

  std::string rawlog_file;              ///< input rawlog; -i overrides (relative: to the CWD,
                                        ///< else to the ini file's folder)
  std::string backend = "ekf";          ///< a name of builtinBackends(); --backend overrides
  std::string ground_truth_file;        ///< landmarks ground truth ("" = next to the rawlog)
  std::string ground_truth_file_robot;  ///< robot path ground truth ("" = next to the rawlog)
  std::string logOutput_dir = "OUT_budget-slam";  ///< output folder; -o overrides
  bool keep_history = true;   ///< keep per-step records in memory (run only; false:
                              ///< flat memory on lifelong runs, see docs/OUTPUTS.md)
  std::size_t max_steps = 0;  ///< stop after this many steps, 0 = the whole rawlog
  std::string kf_implementation = "CRangeBearingKFSLAM2D";  ///< only the 2D filter is supported
  bool save_3d_scene = true;  ///< write map.3Dscene (MRPT's SceneViewer3D) beside map.png
  /// Write kf_state_<step>.3Dscene after every step that is a multiple of this, 0 = never: from
  /// kf-slam's SAVE_3D_SCENES (here false unless written) and SAVE_LOG_FREQUENCY (default 1)
  /// [steps]
  std::size_t scene_every_steps = 0;

  /// Every key read here, kf-slam's and budget-slam's own (`backend`, `max_steps`,
  /// `keep_history`, `save_3d_scene`): name, field, check and unit (the defaults are the
  /// initializers above). The kf-slam keys read nowhere are in ekf::mrptKfSlamIniKeys().
  static const OptionTable<MappingOptions>& table();
  static const std::vector<std::string>& backends();  ///< builtinBackends().names()
};

}  // namespace budget_slam::runs
