#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

const EnumNames<Correspondence>& correspondenceNames() {
  static const EnumNames<Correspondence> names = {{"auto", Correspondence::Auto},
                                                  {"ids", Correspondence::Ids},
                                                  {"search", Correspondence::Search}};
  return names;
}

const EnumNames<WindowFitMode>& windowFitModeNames() {
  static const EnumNames<WindowFitMode> names = {{"window", WindowFitMode::Window},
                                                 {"window_priors", WindowFitMode::WindowPriors},
                                                 {"latest", WindowFitMode::Latest}};
  return names;
}

const OptionTable<WakeUpOptions>& WakeUpOptions::table() {
  using O = WakeUpOptions;
  static const OptionTable<O> t = {
      option::integer("max_steps", &O::max_steps, 1, 100000, "[steps]"),
      option::choice("correspondence", &O::correspondence, correspondenceNames(),
                     "auto | ids | search"),
      option::integer("min_landmarks", &O::min_landmarks, 2, 100000, "[landmarks]"),
      option::integer("search_min_landmarks", &O::search_min_landmarks, 3, 100000, "[landmarks]"),
      option::real("gate_chi2", &O::gate_chi2, 1e-6, 1e6, "chi-square, 2 dof"),
      option::integer("ambiguity_margin", &O::ambiguity_margin, 1, 100000, "[landmarks]"),
      option::real("distinct_xy", &O::distinct_xy, 1e-6, 1e6, "[m]"),
      option::real("distinct_yaw_deg", &O::distinct_yaw_deg, 1e-6, 180, "[deg]"),
      option::real("miss_weight", &O::miss_weight, 0, 100, "[landmarks]"),
      option::real("merge_chi2", &O::merge_chi2, 0, 1e6, "chi-square, 2 dof"),
      option::real("min_pair_distance", &O::min_pair_distance, 0, 1e6, "[m]"),
      option::integer("max_hypotheses", &O::max_hypotheses, 1, 1000000000, "[hypotheses]"),
      option::integer("seed", &O::seed, 0),
      option::real("max_std_xy", &O::max_std_xy, 1e-9, 1e6, "[m]"),
      option::real("max_std_yaw_deg", &O::max_std_yaw_deg, 1e-9, 180, "[deg]"),
      option::choice("fit", &O::fit, windowFitModeNames(), "window | window_priors | latest"),
      option::stddev("no_odometry_std_xy", &O::no_odometry_std_xy, "[m]"),
      option::stddev("no_odometry_std_yaw_deg", &O::no_odometry_std_yaw_deg, "[deg]"),
  };
  return t;
}

}  // namespace budget_slam::wakeup
