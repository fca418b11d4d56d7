#include "budget_slam/localization/LocalizationOptions.h"

namespace budget_slam::runs {

const OptionTable<LocalizationOptions>& LocalizationOptions::table() {
  using O = LocalizationOptions;
  static const OptionTable<O> t = {
      option::real("lost_threshold", &O::lost_threshold, 1e-9, 1e9, "[m]"),
      option::real("start_std_xy", &O::start_std_xy, 0, 1e6, "[m]"),
      option::real("start_std_yaw_deg", &O::start_std_yaw_deg, 0, 360, "[deg]"),
      option::real("gate_chi2", &O::gate_chi2, 0, 1e12, "chi-square, 2 dof; 0 = no gate"),
      option::integer("recover_after_steps", &O::recover_after_steps, 0, 1000000,
                      "[steps], 0 = no recovery"),
      option::integer("recovery_window_steps", &O::recovery_window_steps, 1, 1000000, "[steps]"),
      option::integer("recovery_min_landmarks", &O::recovery_min_landmarks, 2, 1000000,
                      "[landmarks]"),
      option::real("place_size", &O::place_size, 0, 1e6,
                   "[m], 0 = a quarter of the sensor's range"),
      option::integer("heading_sectors", &O::heading_sectors, 0, 360,
                      "0 = from the sensor's field of view"),
      option::real("success_xy", &O::success_xy, 0, 1e9, "[m]"),
      option::real("success_yaw_deg", &O::success_yaw_deg, 0, 360, "[deg]"),
      option::integer("max_map_landmarks", &O::max_map_landmarks, 0, 20000, "[landmarks]"),
      option::integer("max_steps", &O::max_steps, 0, std::numeric_limits<long long>::max(),
                      "[steps], 0 = all"),
  };
  return t;
}

}  // namespace budget_slam::runs
