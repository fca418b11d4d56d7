#include "budget_slam/reducers/ActiveMinimization.h"

#include <algorithm>
#include <cmath>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/gaussian/GaussianStateBackend.h"

namespace budget_slam::reducers {

std::vector<GreedyStep> greedySequence(Backend& scratch, std::vector<LandmarkId> candidates) {
  std::vector<GreedyStep> out;
  out.reserve(candidates.size());
  while (!candidates.empty()) {
    // One information gain per candidate an iteration: seconds on a long run's graph. Nothing is
    // dropped from the real map here, so a stop request can end it at once.
    Cancellation::check();
    // Alg. 4: the least informative landmark, ties to the lowest id.
    const auto gains = scratch.informationGain(candidates);
    std::size_t best = 0;
    for (std::size_t i = 1; i < candidates.size(); ++i)
      if (gains[i] < gains[best] || (gains[i] == gains[best] && candidates[i] < candidates[best]))
        best = i;
    out.push_back({candidates[best], gains[best]});
    scratch.removeLandmark(candidates[best]);
    candidates.erase(candidates.begin() + static_cast<long>(best));
  }
  return out;
}

std::vector<double> objectiveValues(const std::vector<double>& gains, std::size_t n_landmarks,
                                    double lambda) {
  double D = 0;
  for (const double d : gains) D = std::max(D, d);
  std::vector<double> rho = {lambda};
  const double N = static_cast<double>(std::max<std::size_t>(1, n_landmarks));
  for (std::size_t k = 1; k <= gains.size(); ++k) {
    const double d = D > 0 ? std::max(0.0, gains[k - 1]) / D : 0.0;
    rho.push_back((1 - lambda) * d + lambda * (N - static_cast<double>(k)) / N);
  }
  return rho;
}

std::size_t objectiveStop(const std::vector<double>& rho) {
  for (std::size_t k = 1; k < rho.size(); ++k)
    if (rho[k] > rho[k - 1]) return k - 1;
  return rho.empty() ? 0 : rho.size() - 1;
}

std::size_t objectiveMinimum(const std::vector<double>& rho) {
  if (rho.empty()) return 0;
  return static_cast<std::size_t>(std::min_element(rho.begin(), rho.end()) - rho.begin());
}

namespace {

bool sameGains(const std::vector<double>& a, const std::vector<double>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > 1e-9 + 1e-6 * std::abs(a[i])) return false;
  return true;
}

/// The look-ahead copy: the application's scratch, or a Gaussian snapshot when it reproduces the
/// backend's own gains.
std::unique_ptr<Backend> scratchFor(const ScheduleContext& ctx,
                                    const std::vector<LandmarkId>& candidates,
                                    const std::string& mode) {
  if (ctx.scratch)
    if (auto copy = ctx.scratch()) return copy;
  const std::string why = "[MutualInformationReducer] mode = " + mode +
                          " needs a look-ahead copy of backend '" + ctx.backend.name() +
                          "' for Alg. 3";
  std::unique_ptr<gaussian::GaussianStateBackend> g;
  try {
    g = std::make_unique<gaussian::GaussianStateBackend>(
        gaussian::GaussianStateBackend::snapshot(ctx.backend, ctx.step));
  } catch (const std::exception& e) {
    throw ConfigError(why + ": its joint covariance is unavailable (" + e.what() + ")");
  }
  if (!sameGains(ctx.backend.informationGain(candidates), g->informationGain(candidates)))
    throw ConfigError(why +
                      ": its information gain is not that of its joint covariance and the "
                      "application provides no scratch copy");
  return g;
}

}  // namespace

void checkLookAhead(const ScheduleContext& ctx, const std::string& mode) {
  if (ctx.scratch && ctx.scratch()) return;
  std::vector<LandmarkId> ids;
  for (const auto& l : ctx.backend.landmarks()) ids.push_back(l.id);
  if (!ids.empty()) scratchFor(ctx, ids, mode);
}

ScheduledDrops activeMinimization(const ScheduleContext& ctx, double lambda, std::size_t pose_lag,
                                  const std::string& reason, bool global_minimum) {
  ScheduledDrops plan;
  plan.reason = reason;
  plan.marginalize_poses = true;
  plan.keep_last_poses = pose_lag;

  const auto landmarks = ctx.backend.landmarks();
  std::vector<LandmarkId> candidates;
  for (const auto& l : landmarks) {
    // "we do not consider landmarks seen by the last P poses" (Sec. IV-C).
    const bool recent = l.last_step <= ctx.step && ctx.step - l.last_step < pose_lag;
    if (!recent) candidates.push_back(l.id);
  }
  if (candidates.empty()) return plan;

  auto scratch = scratchFor(ctx, candidates, reason);
  // Alg. 5 line 5: the gains are those at the optimum Theta* of the graph so far (the graph's
  // incremental schedule leaves the latest poses dead-reckoned between updates).
  if (PoseHistoryBackend* h = poseHistory(scratch.get())) h->finish();
  const auto sequence = greedySequence(*scratch, candidates);
  std::vector<double> gains;
  for (const auto& s : sequence) gains.push_back(s.gain);
  const std::vector<double> rho = objectiveValues(gains, landmarks.size(), lambda);
  const std::size_t k = global_minimum ? objectiveMinimum(rho) : objectiveStop(rho);
  for (std::size_t i = 0; i < k; ++i) plan.drops.push_back({sequence[i].id, sequence[i].gain});
  return plan;
}

}  // namespace budget_slam::reducers
