#include "budget_slam/metrics/MetricsOptions.h"

#include <ostream>

#include "budget_slam/core/IniSection.h"

namespace budget_slam::metrics {

void MetricsOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                        const std::string& section) {
  const IniSection s(ini, section);
  eig_max_rows =
      static_cast<std::size_t>(s.readInt("eig_max_rows", static_cast<long long>(eig_max_rows), 0));
  reloc_min_landmarks = static_cast<std::size_t>(
      s.readInt("reloc_min_landmarks", static_cast<long long>(reloc_min_landmarks), 1, 1000000));
  reloc_match_chi2 = s.readDouble("reloc_match_chi2", reloc_match_chi2, 0, 1e12);
}

void MetricsOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "eig_max_rows             = " << eig_max_rows << "\n";
  out << "reloc_min_landmarks      = " << reloc_min_landmarks << "\n";
  out << "reloc_match_chi2         = " << reloc_match_chi2 << "\n";
}

}  // namespace budget_slam::metrics
