#include "budget_slam/reducers/KMeans.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace budget_slam::reducers {

std::uint64_t SplitMix64::next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double KMeans::distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Distance d) {
  const Eigen::Vector2d v = a - b;
  return d == Distance::L1 ? std::abs(v.x()) + std::abs(v.y()) : std::hypot(v.x(), v.y());
}

std::vector<std::size_t> KMeans::seedIndices(const std::vector<Eigen::Vector2d>& points,
                                             std::size_t k, Distance d, std::uint64_t seed) {
  const std::size_t n = points.size();
  std::vector<std::size_t> chosen;
  if (n == 0) return chosen;
  k = std::clamp<std::size_t>(k, 1, n);
  SplitMix64 rng(seed);
  std::vector<bool> taken(n, false);
  const auto first =
      std::min(n - 1, static_cast<std::size_t>(rng.uniform() * static_cast<double>(n)));
  chosen.push_back(first);
  taken[first] = true;
  // D(x): distance of each point to its nearest chosen centre.
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  while (chosen.size() < k) {
    const Eigen::Vector2d& c = points[chosen.back()];
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      nearest[i] = std::min(nearest[i], distance(points[i], c, d));
      total += taken[i] ? 0.0 : nearest[i] * nearest[i];  // sequential sum: same order everywhere
    }
    std::size_t pick = n;
    if (total > 0) {
      // Draw with probability proportional to D(x)^2.
      const double r = rng.uniform() * total;
      double cum = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (taken[i] || nearest[i] == 0) continue;
        cum += nearest[i] * nearest[i];
        pick = i;
        if (cum > r) break;
      }
    } else {
      // Every remaining point coincides with a centre: the lowest free index.
      for (std::size_t i = 0; i < n && pick == n; ++i)
        if (!taken[i]) pick = i;
    }
    chosen.push_back(pick);
    taken[pick] = true;
  }
  return chosen;
}

std::vector<std::size_t> KMeans::assign(const std::vector<Eigen::Vector2d>& points,
                                        const std::vector<Eigen::Vector2d>& centres, Distance d) {
  std::vector<std::size_t> label(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const double dc = distance(points[i], centres[c], d);
      if (dc < best) best = dc, label[i] = c;  // strict: ties to the lowest index
    }
  }
  return label;
}

namespace {

/// Gives each empty cluster the point farthest from its own centre among clusters holding at
/// least two points. Returns how many clusters were refilled.
std::size_t refillEmpty(const std::vector<Eigen::Vector2d>& points,
                        const std::vector<Eigen::Vector2d>& centres, KMeans::Distance d,
                        std::vector<std::size_t>& label) {
  std::vector<std::size_t> size(centres.size(), 0);
  for (const auto l : label) ++size[l];
  std::size_t refilled = 0;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (size[c] > 0) continue;
    std::size_t far = points.size();
    double far_d = -1;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (size[label[i]] < 2) continue;
      const double di = KMeans::distance(points[i], centres[label[i]], d);
      if (di > far_d) far = i, far_d = di;
    }
    // k <= N guarantees a cluster with two or more points while one is empty; only non-finite
    // points (a diverged estimate) leave none farther than -1: leave the cluster empty then.
    if (far == points.size()) break;
    --size[label[far]];
    label[far] = c;
    size[c] = 1;
    ++refilled;
  }
  return refilled;
}

}  // namespace

KMeans::Result KMeans::cluster(const std::vector<Eigen::Vector2d>& points, const Options& options) {
  Result res;
  const std::size_t n = points.size();
  if (n == 0) return res;
  const std::size_t k = std::clamp<std::size_t>(options.k, 1, n);
  for (const auto i : seedIndices(points, k, options.distance, options.seed))
    res.centres.push_back(points[i]);

  const std::size_t max_it = std::max<std::size_t>(1, options.max_iterations);
  std::vector<std::size_t> label;
  while (res.iterations < max_it) {
    ++res.iterations;
    std::vector<std::size_t> next = assign(points, res.centres, options.distance);
    res.reseeds += refillEmpty(points, res.centres, options.distance, next);

    std::vector<Eigen::Vector2d> sum(k, Eigen::Vector2d::Zero());
    std::vector<std::size_t> count(k, 0);
    for (std::size_t i = 0; i < n; ++i) sum[next[i]] += points[i], ++count[next[i]];
    for (std::size_t c = 0; c < k; ++c) res.centres[c] = sum[c] / static_cast<double>(count[c]);

    const bool same = next == label;
    label = std::move(next);
    if (same) {
      res.converged = true;
      break;
    }
  }
  res.label = std::move(label);
  return res;
}

}  // namespace budget_slam::reducers
