#include "budget_slam/wakeup/GlobalLocalizer.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/wakeup/PoseFit.h"
#include "budget_slam/wakeup/WindowFit.h"

namespace budget_slam::wakeup {
namespace {

/// Information whose scaled form (unit diagonal) has an eigenvalue below this fixes no pose: one
/// direction (e.g. the rotation about a single landmark) is unobserved.
constexpr double kDegenerateEigenvalue = 1e-9;

/// By id: more than this share of the distinct map landmarks the readings name must agree with the
/// pose found, a strict majority (docs/ALGORITHMS.md "Waking up on a saved map").
constexpr double kMinAgreeingShare = 0.5;

std::size_t distinctLandmarks(const std::vector<Pairing>& pairs) {
  std::set<std::size_t> s;
  for (const auto& p : pairs) s.insert(p.landmark);
  return s.size();
}

WakeUpResult notFound(WakeUpReason why, std::size_t landmarks = 0) {
  WakeUpResult r;
  r.status = WakeUpStatus::NotFound;
  r.reason = why;
  r.landmarks = landmarks;
  return r;
}

}  // namespace

const char* statusName(WakeUpStatus s) {
  switch (s) {
    case WakeUpStatus::Found:
      return "found";
    case WakeUpStatus::NotFound:
      return "not_found";
    case WakeUpStatus::Ambiguous:
      return "ambiguous";
  }
  return "";
}

const char* reasonName(WakeUpReason r) {
  switch (r) {
    case WakeUpReason::None:
      return "";
    case WakeUpReason::TooFewLandmarks:
      return "too_few_landmarks";
    case WakeUpReason::Degenerate:
      return "degenerate";
    case WakeUpReason::Inconsistent:
      return "inconsistent";
    case WakeUpReason::TooUncertain:
      return "too_uncertain";
  }
  return "";
}

GlobalLocalizer::GlobalLocalizer(std::vector<LandmarkView> map, const WakeUpOptions& options,
                                 const ReadingNoise& noise)
    : options_(options), noise_(noise), index_(map), window_(noise, options), rng_(options.seed) {
  for (std::size_t i = 0; i < index_.map().size(); ++i) by_id_[index_.map()[i].id] = i;
}

bool GlobalLocalizer::finished() const {
  return result_.status == WakeUpStatus::Found || window_.steps() >= options_.max_steps;
}

const WakeUpResult& GlobalLocalizer::add(const Step& step) {
  if (finished()) return result_;
  window_.add(step);
  result_ = attempt();
  return result_;
}

WakeUpResult GlobalLocalizer::attempt() {
  const std::vector<LocalReading> readings = window_.readings();
  bool ids = options_.correspondence == Correspondence::Ids;
  if (options_.correspondence == Correspondence::Auto)
    ids = !readings.empty() && std::all_of(readings.begin(), readings.end(),
                                           [](const auto& r) { return r.id != kNoLandmarkId; });
  WakeUpResult r = ids ? byIds(readings) : bySearch(readings);
  r.by_ids = ids;
  r.step = window_.latest();
  r.steps_used = window_.steps();
  r.readings = readings.size();
  return r;
}

WakeUpResult GlobalLocalizer::byIds(const std::vector<LocalReading>& readings) {
  std::vector<Pairing> pairs;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const auto it = by_id_.find(readings[i].id);
    if (readings[i].id != kNoLandmarkId && it != by_id_.end()) pairs.push_back({i, it->second});
  }
  const std::size_t distinct = distinctLandmarks(pairs);
  if (distinct < options_.min_landmarks) return notFound(WakeUpReason::TooFewLandmarks, distinct);
  WakeUpResult r = refineAndJudge(std::nullopt, readings, std::move(pairs), options_.min_landmarks);
  // Dropping the worst reading one at a time ends, on any map, with two landmarks that fit: an id
  // is a claim that the reading and the landmark are one, so a pose that most of the claimed
  // landmarks do not agree with (half or more) is a map of another place, not a pose.
  if (r.status == WakeUpStatus::Found &&
      static_cast<double>(r.landmarks) <= kMinAgreeingShare * static_cast<double>(distinct)) {
    r.status = WakeUpStatus::NotFound;
    r.reason = WakeUpReason::Inconsistent;
  }
  return r;
}

WakeUpResult GlobalLocalizer::bySearch(const std::vector<LocalReading>& readings) {
  const auto local = mergeReadings(readings, options_.merge_chi2);
  if (local.size() < options_.search_min_landmarks)
    return notFound(WakeUpReason::TooFewLandmarks, local.size());
  const SearchOutcome s = searchPose(local, index_, window_.views(), options_, rng_);
  const std::size_t best = s.best ? s.best->landmarks : 0;
  const std::size_t second = s.runner_up ? s.runner_up->landmarks : 0;
  WakeUpResult r;
  if (best < options_.search_min_landmarks) {
    r = notFound(WakeUpReason::Inconsistent, best);
  } else if (s.crowded ||
             (s.runner_up && s.runner_up->score + static_cast<double>(options_.ambiguity_margin) >
                                 s.best->score)) {
    r.status = WakeUpStatus::Ambiguous;
    r.reason = WakeUpReason::None;
    r.landmarks = best;
  } else {
    std::vector<Pairing> pairs;
    for (const auto& [c, m] : s.best->matches)
      for (const auto i : local[c].readings) pairs.push_back({i, m});
    r = refineAndJudge(s.best->pose, readings, std::move(pairs), options_.search_min_landmarks);
  }
  r.hypotheses = s.hypotheses;
  r.runner_up = second;
  r.score = s.best ? s.best->score : 0;
  r.runner_up_score = s.runner_up ? s.runner_up->score : 0;
  return r;
}

WakeUpResult GlobalLocalizer::refineAndJudge(std::optional<Pose2> start,
                                             const std::vector<LocalReading>& readings,
                                             std::vector<Pairing> pairs,
                                             std::size_t min_landmarks) {
  const auto& map = index_.map();
  const bool refit = !start.has_value();
  Refinement ref;
  while (true) {
    Cancellation::check();  // one reading dropped a round: as many rounds as readings
    if (refit) {
      std::vector<Eigen::Vector2d> local, global;
      std::vector<double> w;
      for (const auto& p : pairs) {
        local.push_back(readings[p.reading].point);
        global.push_back(map[p.landmark].mean);
        w.push_back(1.0 / (readings[p.reading].point_cov.trace() + map[p.landmark].cov.trace()));
      }
      start = fitRigid(local, global, w);
      if (!start) return notFound(WakeUpReason::Degenerate, distinctLandmarks(pairs));
    }
    ref = refinePose(*start, readings, map, pairs, noise_);
    if (!ref.converged) break;
    // The reading furthest outside the gate goes, one at a time: an outlier drags the pose and
    // so inflates the others' innovations.
    const auto worst = std::max_element(ref.chi2.begin(), ref.chi2.end()) - ref.chi2.begin();
    if (ref.chi2[static_cast<std::size_t>(worst)] <= options_.gate_chi2) break;
    pairs.erase(pairs.begin() + worst);
    if (distinctLandmarks(pairs) < min_landmarks)
      return notFound(WakeUpReason::Inconsistent, distinctLandmarks(pairs));
    if (!refit) start = ref.pose;
  }
  if (ref.converged && options_.fit != WindowFitMode::Latest) {
    // The window's poses fitted jointly on the readings the latest-pose fit kept, the outliers
    // of the joint fit dropped the same way (docs/ALGORITHMS.md "Over a window").
    const std::vector<WindowStep> steps = window_.gathered();
    const WindowLandmarks landmarks =
        options_.fit == WindowFitMode::Window ? WindowLandmarks::Fixed : WindowLandmarks::Priors;
    while (true) {
      ref = fitWindow(ref.pose, steps, readings, map, pairs, noise_, landmarks);
      if (!ref.converged) break;
      const auto worst = std::max_element(ref.chi2.begin(), ref.chi2.end()) - ref.chi2.begin();
      if (ref.chi2[static_cast<std::size_t>(worst)] <= options_.gate_chi2) break;
      pairs.erase(pairs.begin() + worst);
      if (distinctLandmarks(pairs) < min_landmarks)
        return notFound(WakeUpReason::Inconsistent, distinctLandmarks(pairs));
    }
  }
  WakeUpResult r;
  r.inliers = pairs.size();
  r.landmarks = distinctLandmarks(pairs);
  r.pose.mean = ref.pose;
  r.pose.cov = ref.cov;
  // Unit-free rank test: the information scaled to a unit diagonal.
  const Eigen::Vector3d d = ref.information.diagonal();
  bool degenerate = !ref.converged || !(d.minCoeff() > 0);
  if (!degenerate) {
    const Eigen::Vector3d s = d.cwiseSqrt().cwiseInverse();
    const Eigen::Matrix3d C = s.asDiagonal() * ref.information * s.asDiagonal();
    degenerate = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues().minCoeff() <
                 kDegenerateEigenvalue;
  }
  if (degenerate) {
    r.status = WakeUpStatus::NotFound;
    r.reason = WakeUpReason::Degenerate;
    return r;
  }
  const double std_xy = std::sqrt(std::max(ref.cov(0, 0), ref.cov(1, 1)));
  const double std_yaw = std::sqrt(ref.cov(2, 2));
  if (std_xy > options_.max_std_xy || std_yaw > options_.max_std_yaw_deg * M_PI / 180) {
    r.status = WakeUpStatus::NotFound;
    r.reason = WakeUpReason::TooUncertain;
    return r;
  }
  r.status = WakeUpStatus::Found;
  r.reason = WakeUpReason::None;
  return r;
}

WakeUpResult wakeUp(const std::vector<LandmarkView>& map, const std::vector<Step>& steps,
                    const WakeUpOptions& options, const ReadingNoise& noise) {
  GlobalLocalizer g(map, options, noise);
  for (const auto& s : steps) {
    if (g.finished()) break;
    g.add(s);
  }
  return g.result();
}

}  // namespace budget_slam::wakeup
