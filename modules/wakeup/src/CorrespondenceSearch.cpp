#include "budget_slam/wakeup/CorrespondenceSearch.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <set>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/wakeup/PoseFit.h"

namespace budget_slam::wakeup {
namespace {

double largestEigenvalue(const Eigen::Matrix2d& m) {
  // Symmetric 2x2: (tr + sqrt(tr^2 - 4 det)) / 2.
  const double tr = m(0, 0) + m(1, 1), det = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  return 0.5 * (tr + std::sqrt(std::max(0.0, tr * tr - 4 * det)));
}

double mahalanobis2(const Eigen::Vector2d& d, const Eigen::Matrix2d& S) {
  return d.dot(S.ldlt().solve(d));
}

/// Variance of |a - b| from the covariances of a and b, along the direction between them.
double distanceVariance(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Matrix2d& Sa, const Eigen::Matrix2d& Sb) {
  const Eigen::Vector2d d = b - a;
  const double n = d.norm();
  if (n == 0) return largestEigenvalue(Sa + Sb);
  const Eigen::Vector2d u = d / n;
  return u.dot((Sa + Sb) * u);
}

bool samePose(const Pose2& a, const Pose2& b, const WakeUpOptions& o) {
  return (a.translation() - b.translation()).norm() <= o.distinct_xy &&
         std::abs(wrapAngle(a.phi - b.phi)) <= o.distinct_yaw_deg * M_PI / 180;
}

}  // namespace

std::vector<LocalLandmark> mergeReadings(const std::vector<LocalReading>& readings,
                                         double merge_chi2) {
  std::vector<LocalLandmark> out;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    // A stop request ends the wake-up within a second however many readings it gathered (each
    // reading is compared with every landmark so far): Ctrl-C, SIGTERM.
    Cancellation::check();
    const LocalReading& r = readings[i];
    std::size_t best = out.size();
    double best_d = merge_chi2;
    for (std::size_t k = 0; k < out.size(); ++k) {
      // One scan reports a landmark once: two readings of a step are two landmarks.
      bool same_step = false;
      for (const auto j : out[k].readings) same_step = same_step || readings[j].step == r.step;
      if (same_step) continue;
      const double d = mahalanobis2(r.point - out[k].point, r.point_cov + out[k].cov);
      if (d <= best_d) {
        best_d = d;
        best = k;
      }
    }
    if (best == out.size()) {
      out.push_back({r.point, r.point_cov, {i}});
      continue;
    }
    LocalLandmark& l = out[best];
    const Eigen::Matrix2d Ia = l.cov.inverse(), Ib = r.point_cov.inverse();
    l.cov = (Ia + Ib).inverse();
    l.point = l.cov * (Ia * l.point + Ib * r.point);
    l.readings.push_back(i);
  }
  return out;
}

MapIndex::MapIndex(const std::vector<LandmarkView>& map) : map_(map) {
  if (map_.empty()) return;
  Eigen::Vector2d lo = map_[0].mean, hi = map_[0].mean;
  for (const auto& l : map_) {
    lo = lo.cwiseMin(l.mean);
    hi = hi.cwiseMax(l.mean);
    max_var_ = std::max(max_var_, largestEigenvalue(l.cov));
  }
  // About one landmark a cell.
  const double area = std::max(1.0, (hi - lo).prod());
  cell_ = std::max(0.5, std::sqrt(area / static_cast<double>(map_.size())));
  origin_ = lo;
  for (std::uint32_t i = 0; i < map_.size(); ++i) {
    const Eigen::Vector2d c = (map_[i].mean - origin_) / cell_;
    grid_[key(static_cast<long>(std::floor(c.x())), static_cast<long>(std::floor(c.y())))]
        .push_back(i);
  }
}

std::int64_t MapIndex::key(long cx, long cy) const {
  // Unsigned: a shift of a negative cell index would be undefined.
  const auto ux = static_cast<std::uint64_t>(static_cast<std::uint32_t>(cx));
  const auto uy = static_cast<std::uint64_t>(static_cast<std::uint32_t>(cy));
  return static_cast<std::int64_t>((ux << 32) | uy);
}

void MapIndex::forEachNear(const Eigen::Vector2d& point, double radius,
                           const std::function<void(std::size_t)>& f) const {
  const Eigen::Vector2d lo = ((point - origin_).array() - radius) / cell_;
  const Eigen::Vector2d hi = ((point - origin_).array() + radius) / cell_;
  const double cells =
      (std::floor(hi.x()) - std::floor(lo.x()) + 1) * (std::floor(hi.y()) - std::floor(lo.y()) + 1);
  if (!std::isfinite(cells) || cells > static_cast<double>(map_.size())) {
    for (std::size_t i = 0; i < map_.size(); ++i) f(i);
    return;
  }
  for (auto cx = static_cast<long>(std::floor(lo.x())); cx <= static_cast<long>(std::floor(hi.x()));
       ++cx)
    for (auto cy = static_cast<long>(std::floor(lo.y()));
         cy <= static_cast<long>(std::floor(hi.y())); ++cy) {
      const auto it = grid_.find(key(cx, cy));
      if (it == grid_.end()) continue;
      for (const auto i : it->second) f(i);
    }
}

std::optional<std::pair<std::size_t, double>> MapIndex::nearest(const Eigen::Vector2d& point,
                                                                const Eigen::Matrix2d& cov,
                                                                double gate_chi2) const {
  std::optional<std::pair<std::size_t, double>> best;
  // Every landmark within the gate lies within this Euclidean radius.
  const double radius = std::sqrt(gate_chi2 * (largestEigenvalue(cov) + max_var_));
  forEachNear(point, radius, [&](std::size_t i) {
    const double d = mahalanobis2(point - map_[i].mean, cov + map_[i].cov);
    if (d <= gate_chi2 && (!best || d < best->second)) best = std::make_pair(i, d);
  });
  return best;
}

const std::vector<MapIndex::Pair>& MapIndex::pairsUpTo(double max_distance) const {
  if (max_distance <= pairs_up_to_) return pairs_;
  pairs_.clear();
  for (std::uint32_t a = 0; a < map_.size(); ++a) {
    Cancellation::check();
    for (std::uint32_t b = a + 1; b < map_.size(); ++b) {
      const double d = (map_[a].mean - map_[b].mean).norm();
      if (d <= max_distance)
        pairs_.push_back(
            {d, a, b, distanceVariance(map_[a].mean, map_[b].mean, map_[a].cov, map_[b].cov)});
    }
  }
  std::sort(pairs_.begin(), pairs_.end(),
            [](const Pair& x, const Pair& y) { return x.distance < y.distance; });
  pairs_up_to_ = max_distance;
  return pairs_;
}

namespace {

/// Each local landmark's nearest map landmark under `pose` within the gate; a map landmark
/// claimed twice keeps the closer local one. map index -> (local index, squared distance).
std::unordered_map<std::size_t, std::pair<std::size_t, double>> agreement(
    const Pose2& pose, const std::vector<LocalLandmark>& local, const MapIndex& index,
    double gate_chi2) {
  const Eigen::Matrix2d R = rot2(pose.phi);
  std::unordered_map<std::size_t, std::pair<std::size_t, double>> claimed;
  for (std::size_t c = 0; c < local.size(); ++c) {
    const auto n = index.nearest(R * local[c].point + pose.translation(),
                                 R * local[c].cov * R.transpose(), gate_chi2);
    if (!n) continue;
    const auto it = claimed.find(n->first);
    if (it == claimed.end() || n->second < it->second.second) claimed[n->first] = {c, n->second};
  }
  return claimed;
}

}  // namespace

Hypothesis scorePose(const Pose2& pose, const std::vector<LocalLandmark>& local,
                     const MapIndex& index, const std::vector<SensorView>& views,
                     const WakeUpOptions& options) {
  const auto claimed = agreement(pose, local, index, options.gate_chi2);
  Hypothesis h;
  h.pose = pose;
  h.landmarks = claimed.size();
  for (const auto& [m, cd] : claimed) {
    h.chi2 += cd.second;
    h.matches.push_back({cd.first, m});
  }
  std::sort(h.matches.begin(), h.matches.end());
  // Negative evidence: map landmarks well in view of a gathered step that nothing agrees with.
  std::set<std::size_t> missed;
  for (const auto& v : views) {
    if (!(v.max_range > 0)) continue;
    const Pose2 sensor = compose(pose, v.sensor);
    const double reach = kInViewRangeShare * v.max_range;
    index.forEachNear(sensor.translation(), reach, [&](std::size_t i) {
      if (claimed.count(i) || missed.count(i)) return;
      const Eigen::Vector2d d = index.map()[i].mean - sensor.translation();
      const double r = d.norm();
      if (r > reach || r < v.min_range) return;
      const double bearing = wrapAngle(std::atan2(d.y(), d.x()) - sensor.phi);
      if (std::abs(bearing) <= v.fov / 2 - kInViewAngleMargin) missed.insert(i);
    });
  }
  h.missed = missed.size();
  h.score = static_cast<double>(h.landmarks) - options.miss_weight * static_cast<double>(h.missed);
  return h;
}

SearchOutcome searchPose(const std::vector<LocalLandmark>& local, const MapIndex& index,
                         const std::vector<SensorView>& views, const WakeUpOptions& options,
                         std::mt19937_64& rng) {
  SearchOutcome out;
  const double gate = options.gate_chi2;
  struct LocalPair {
    std::size_t i, j;
    double distance, var;
    std::size_t from, to;  ///< window of map pairs, [from, to)
  };
  std::vector<LocalPair> lpairs;
  double longest = 0, widest = 0;
  for (std::size_t i = 0; i < local.size(); ++i)
    for (std::size_t j = i + 1; j < local.size(); ++j) {
      const double d = (local[i].point - local[j].point).norm();
      if (d < options.min_pair_distance) continue;
      const double var =
          distanceVariance(local[i].point, local[j].point, local[i].cov, local[j].cov);
      lpairs.push_back({i, j, d, var, 0, 0});
      longest = std::max(longest, d);
      widest = std::max(widest, var);
    }
  if (lpairs.empty() || index.map().size() < 2) return out;
  // A map pair's distance variance is at most twice the largest landmark variance.
  const double max_pair_var = 2 * index.maxVariance();
  const auto& mpairs = index.pairsUpTo(longest + std::sqrt(gate * (widest + max_pair_var)));
  // Each local pair's window of map pairs whose distance may agree (the exact check, with the
  // pair's own variance, is per pair below).
  std::size_t total = 0;
  for (auto& lp : lpairs) {
    const double w = std::sqrt(gate * (lp.var + max_pair_var));
    const auto cmp = [](const MapIndex::Pair& p, double d) { return p.distance < d; };
    lp.from = static_cast<std::size_t>(
        std::lower_bound(mpairs.begin(), mpairs.end(), lp.distance - w, cmp) - mpairs.begin());
    lp.to = static_cast<std::size_t>(
        std::lower_bound(mpairs.begin(), mpairs.end(), lp.distance + w * (1 + 1e-12), cmp) -
        mpairs.begin());
    total += 2 * (lp.to - lp.from);
  }

  // First pass: the agreement of every hypothesis (cheap: no negative evidence).
  struct Counted {
    Pose2 pose;
    std::size_t landmarks;
    double chi2;
  };
  std::vector<Counted> counted;
  const auto tryPair = [&](const LocalPair& lp, const MapIndex::Pair& mp, bool swapped) {
    Cancellation::check();  // up to max_hypotheses of them, each scored against the map
    const double dd = lp.distance - mp.distance;
    if (dd * dd > gate * (lp.var + mp.var)) return;
    const auto& m = index.map();
    const std::vector<Eigen::Vector2d> pl = {local[lp.i].point, local[lp.j].point};
    std::vector<Eigen::Vector2d> pm = {m[mp.a].mean, m[mp.b].mean};
    if (swapped) std::swap(pm[0], pm[1]);
    const auto pose = fitRigid(pl, pm, {1.0, 1.0});
    if (!pose) return;
    double chi2 = 0;
    const auto claimed = agreement(*pose, local, index, gate);
    for (const auto& [unused, cd] : claimed) chi2 += cd.second;
    counted.push_back({*pose, claimed.size(), chi2});
  };
  if (total <= options.max_hypotheses) {
    for (const auto& lp : lpairs)
      for (std::size_t k = lp.from; k < lp.to; ++k) {
        tryPair(lp, mpairs[k], false);
        tryPair(lp, mpairs[k], true);
      }
  } else {
    // RANSAC: draw (local pair, map pair, order) uniformly among the candidates.
    std::vector<std::size_t> cumulative;
    std::size_t acc = 0;
    for (const auto& lp : lpairs) cumulative.push_back(acc += 2 * (lp.to - lp.from));
    std::uniform_int_distribution<std::size_t> draw(0, total - 1);
    for (std::size_t n = 0; n < options.max_hypotheses; ++n) {
      const std::size_t x = draw(rng);
      const std::size_t l = static_cast<std::size_t>(
          std::upper_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
      const std::size_t offset = x - (l == 0 ? 0 : cumulative[l - 1]);
      tryPair(lpairs[l], mpairs[lpairs[l].from + offset / 2], offset % 2 == 1);
    }
  }
  out.hypotheses = counted.size();
  if (counted.empty()) return out;
  std::stable_sort(counted.begin(), counted.end(), [](const Counted& a, const Counted& b) {
    return a.landmarks != b.landmarks ? a.landmarks > b.landmarks : a.chi2 < b.chi2;
  });

  // Second pass: one pose a place, most agreement first, scored in full. A score never exceeds
  // the agreement, so once the agreement falls ambiguity_margin below the best score, no later
  // pose can be the best or come close to it.
  // With too little agreement anywhere the wake-up fails whatever the rest says: the best counted
  // pose is reported as it is.
  if (counted[0].landmarks < options.search_min_landmarks) {
    out.best = scorePose(counted[0].pose, local, index, {}, options);
    return out;
  }
  std::vector<Hypothesis> places;
  double best_score = -1e300;
  const auto margin = static_cast<double>(options.ambiguity_margin);
  for (const auto& c : counted) {
    Cancellation::check();
    if (static_cast<double>(c.landmarks) <= best_score - margin) break;
    bool seen = false;
    for (const auto& p : places) seen = seen || samePose(p.pose, c.pose, options);
    if (seen) continue;
    if (places.size() == kMaxPlacesScored) {
      // More places than this could still rival the best: too many to tell apart.
      out.crowded = true;
      break;
    }
    places.push_back(scorePose(c.pose, local, index, views, options));
    best_score = std::max(best_score, places.back().score);
  }
  const auto better = [](const Hypothesis& a, const Hypothesis& b) {
    return a.score != b.score ? a.score > b.score : a.chi2 < b.chi2;
  };
  std::stable_sort(places.begin(), places.end(), better);
  out.best = places[0];
  // The runner-up explains the readings otherwise: it shares at most one pairing with the best.
  // Two shared pairings fix nearly the same pose, so such a hypothesis is the best one fitted
  // worse (a neighbouring landmark caught in the gate), not a rival.
  const std::set<std::pair<std::size_t, std::size_t>> best_matches(out.best->matches.begin(),
                                                                   out.best->matches.end());
  for (std::size_t k = 1; k < places.size(); ++k) {
    std::size_t shared = 0;
    for (const auto& m : places[k].matches) shared += best_matches.count(m);
    if (shared >= 2) continue;
    out.runner_up = places[k];
    break;
  }
  return out;
}

}  // namespace budget_slam::wakeup
