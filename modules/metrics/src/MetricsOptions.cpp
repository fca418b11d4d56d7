#include "budget_slam/metrics/MetricsOptions.h"

namespace budget_slam::metrics {

const OptionTable<MetricsOptions>& MetricsOptions::table() {
  using O = MetricsOptions;
  static const OptionTable<O> t = {
      option::integer("eig_max_rows", &O::eig_max_rows, 0, std::numeric_limits<long long>::max(),
                      "[rows]"),
      option::integer("reloc_min_landmarks", &O::reloc_min_landmarks, 1, 1000000, "[landmarks]"),
      option::real("reloc_match_chi2", &O::reloc_match_chi2, 0, 1e12, "chi-square, 2 dof"),
  };
  return t;
}

}  // namespace budget_slam::metrics
