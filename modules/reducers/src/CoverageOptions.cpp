#include "budget_slam/reducers/CoverageOptions.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::reducers {

namespace {

const EnumNames<KMeans::Distance>& distanceNames() {
  static const EnumNames<KMeans::Distance> n = {{"L1", KMeans::Distance::L1},
                                                {"L2", KMeans::Distance::L2}};
  return n;
}

}  // namespace

const OptionTable<CoverageOptions>& CoverageOptions::table() {
  using O = CoverageOptions;
  static const OptionTable<O> t = {
      option::real("cluster_ratio", &O::cluster_ratio, 1e-9, 1.0, "k / N, in (0, 1]"),
      option::choice("distance", &O::distance, distanceNames()),
      option::integer("max_iterations", &O::max_iterations, 1,
                      std::numeric_limits<long long>::max(), "[iterations]"),
      option::integer("seed", &O::seed, 0),
  };
  return t;
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
