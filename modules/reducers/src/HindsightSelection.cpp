#include "budget_slam/reducers/HindsightSelection.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace budget_slam::reducers {
namespace {

/// log det of a symmetric positive definite 3x3 matrix.
double logDet(const Eigen::Matrix3d& m) {
  const Eigen::LLT<Eigen::Matrix3d> llt(m);
  const Eigen::Matrix3d& L = llt.matrixLLT();
  return 2 * (std::log(L(0, 0)) + std::log(L(1, 1)) + std::log(L(2, 2)));
}

void sortUnique(std::vector<LandmarkId>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

/// For each candidate (by index), the places that read it and its information there.
struct Incidence {
  std::vector<std::vector<std::pair<std::size_t, const Eigen::Matrix3d*>>> of;
};

Incidence incidence(const std::vector<PlaceReadings>& places,
                    const std::vector<LandmarkId>& candidates) {
  std::unordered_map<LandmarkId, std::size_t> index;
  for (std::size_t i = 0; i < candidates.size(); ++i) index[candidates[i]] = i;
  Incidence in;
  in.of.resize(candidates.size());
  for (std::size_t p = 0; p < places.size(); ++p)
    for (std::size_t j = 0; j < places[p].ids.size(); ++j) {
      const auto it = index.find(places[p].ids[j]);
      if (it != index.end()) in.of[it->second].push_back({p, &places[p].info[j]});
    }
  return in;
}

LogDetSelection finish(const std::vector<PlaceReadings>& places, const Eigen::Matrix3d& prior,
                       std::vector<LandmarkId> selection) {
  LogDetSelection out;
  std::sort(selection.begin(), selection.end());
  out.selection = std::move(selection);
  out.objective = logDetObjective(places, prior, out.selection);
  out.gain = out.objective - logDetObjective(places, prior, {});
  return out;
}

}  // namespace

double logDetObjective(const std::vector<PlaceReadings>& places, const Eigen::Matrix3d& prior,
                       const std::vector<LandmarkId>& selection) {
  std::vector<LandmarkId> s = selection;
  sortUnique(s);
  double f = 0;
  for (const PlaceReadings& p : places) {
    Eigen::Matrix3d lambda = prior;
    for (std::size_t j = 0; j < p.ids.size(); ++j)
      if (std::binary_search(s.begin(), s.end(), p.ids[j])) lambda += p.info[j];
    f += logDet(lambda);
  }
  return f;
}

LogDetSelection greedyLogDetSelection(const std::vector<PlaceReadings>& places,
                                      const Eigen::Matrix3d& prior,
                                      std::vector<LandmarkId> candidates, std::size_t k) {
  sortUnique(candidates);
  if (k >= candidates.size()) return finish(places, prior, candidates);
  const Incidence in = incidence(places, candidates);
  std::vector<Eigen::Matrix3d> lambda(places.size(), prior);
  std::vector<double> logdet(places.size(), logDet(prior));
  std::vector<bool> chosen(candidates.size(), false);
  std::vector<LandmarkId> selection;
  while (selection.size() < k) {
    // The largest gain; candidates are in id order, so the first of equal gains has the lowest id.
    std::size_t best = candidates.size();
    double best_gain = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (chosen[i]) continue;
      double gain = 0;
      for (const auto& [p, info] : in.of[i]) gain += logDet(lambda[p] + *info) - logdet[p];
      if (gain > best_gain) best = i, best_gain = gain;
    }
    chosen[best] = true;
    selection.push_back(candidates[best]);
    for (const auto& [p, info] : in.of[best]) {
      lambda[p] += *info;
      logdet[p] = logDet(lambda[p]);
    }
  }
  return finish(places, prior, std::move(selection));
}

LogDetSelection exhaustiveLogDetSelection(const std::vector<PlaceReadings>& places,
                                          const Eigen::Matrix3d& prior,
                                          std::vector<LandmarkId> candidates, std::size_t k,
                                          std::size_t max_subsets) {
  sortUnique(candidates);
  const std::size_t n = candidates.size();
  if (k >= n) return finish(places, prior, candidates);
  // C(n, k), stopped as soon as it passes the limit.
  double subsets = 1;
  for (std::size_t i = 0; i < k; ++i) subsets = subsets * static_cast<double>(n - i) / (i + 1);
  if (subsets > static_cast<double>(max_subsets))
    throw std::length_error("exhaustive selection: " + std::to_string(n) + " choose " +
                            std::to_string(k) + " subsets exceed the limit of " +
                            std::to_string(max_subsets));
  // Every k-subset in lexicographic order of its indices; the first of equal values stays.
  std::vector<std::size_t> idx(k);
  for (std::size_t i = 0; i < k; ++i) idx[i] = i;
  std::vector<LandmarkId> best;
  double best_f = -std::numeric_limits<double>::infinity();
  std::vector<LandmarkId> s(k);
  while (true) {
    for (std::size_t i = 0; i < k; ++i) s[i] = candidates[idx[i]];
    const double f = logDetObjective(places, prior, s);
    if (f > best_f) best_f = f, best = s;
    // Next combination.
    std::size_t i = k;
    while (i > 0 && idx[i - 1] == n - k + (i - 1)) --i;
    if (i == 0) break;
    ++idx[i - 1];
    for (std::size_t j = i; j < k; ++j) idx[j] = idx[j - 1] + 1;
  }
  return finish(places, prior, std::move(best));
}

}  // namespace budget_slam::reducers
