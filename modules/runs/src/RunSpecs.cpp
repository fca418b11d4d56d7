#include "budget_slam/runs/RunSpecs.h"

#include <filesystem>

namespace budget_slam::runs {

runs::DriverSpec driverSpec(const RunConfig& rc) {
  runs::DriverSpec d;
  d.backend = rc.mapping.backend;
  d.budget = rc.budget;
  d.keep_history = rc.mapping.keep_history;
  d.save_3d_scene = rc.mapping.save_3d_scene;
  d.scene_every_steps = rc.mapping.scene_every_steps;
  d.rawlog_name = std::filesystem::path(rc.mapping.rawlog_file).filename().string();
  return d;
}

}  // namespace budget_slam::runs
