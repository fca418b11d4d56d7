#pragma once
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace budget_slam::metrics {

/// [Metrics]: limits of the comparison against the reference run.
struct MetricsOptions : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "Metrics";

  /// EIG needs the eigenvalues of a dense covariance difference (O(n^3)); above this many rows it
  /// is skipped and reported empty [rows]. Default: 3000 (about 1500 landmarks or 1000 poses).
  std::size_t eig_max_rows = 3000;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;
  static std::vector<std::string> keys() { return {"eig_max_rows"}; }
};

}  // namespace budget_slam::metrics
