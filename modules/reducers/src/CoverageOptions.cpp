#include "budget_slam/reducers/CoverageOptions.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "budget_slam/core/IniSection.h"

namespace budget_slam::reducers {

void CoverageOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                         const std::string& section) {
  const IniSection s(ini, section);
  cluster_ratio = s.readDouble("cluster_ratio", cluster_ratio, 1e-9, 1.0);
  const std::string d =
      s.readChoice("distance", distance == KMeans::Distance::L1 ? "L1" : "L2", {"L1", "L2"});
  distance = d == "L1" ? KMeans::Distance::L1 : KMeans::Distance::L2;
  max_iterations = static_cast<std::size_t>(
      s.readInt("max_iterations", static_cast<long long>(max_iterations), 1));
  seed = static_cast<std::uint64_t>(s.readInt("seed", static_cast<long long>(seed), 0));
}

void CoverageOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "cluster_ratio            = " << cluster_ratio << "\n";
  out << "distance                 = " << (distance == KMeans::Distance::L1 ? "L1" : "L2") << "\n";
  out << "max_iterations           = " << max_iterations << "\n";
  out << "seed                     = " << seed << "\n";
}

std::vector<std::string> CoverageOptions::keys() {
  return {"cluster_ratio", "distance", "max_iterations", "seed"};
}

KMeans::Options CoverageOptions::kmeans(std::size_t n_points) const {
  KMeans::Options o;
  // round() of the paper's "1/4 of the currently known landmarks", at least one cluster.
  const auto k =
      static_cast<std::size_t>(std::llround(cluster_ratio * static_cast<double>(n_points)));
  o.k = std::max<std::size_t>(1, k);
  o.distance = distance;
  o.max_iterations = max_iterations;
  o.seed = seed;
  return o;
}

}  // namespace budget_slam::reducers
