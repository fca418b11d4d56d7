#include <gtest/gtest.h>

#include <csignal>
#include <map>
#include <set>

#include "FakeBackend.h"
#include "TestStates.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/ActiveMinimization.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/MutualInformationReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

/// A backend whose gains change as landmarks go: gain(L) = base[L] + sum of coupling[L][R] over
/// the removed R. Counts pose marginalizations.
class ScriptedBackend : public FakeBackend, public PoseHistoryBackend {
 public:
  using FakeBackend::FakeBackend;
  std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const override {
    std::vector<double> out;
    for (const auto id : ids) {
      double g = base.at(id);
      for (const auto r : removed)
        if (coupling.count({id, r})) g += coupling.at({id, r});
      out.push_back(g);
    }
    return out;
  }
  void removeLandmark(LandmarkId id) override {
    FakeBackend::removeLandmark(id);
    removed.push_back(id);
  }
  std::size_t marginalizePosesWithoutLandmarks(std::size_t keep_last) override {
    marginalize_calls.push_back(keep_last);
    return 7;
  }
  void finish() override {}
  std::map<LandmarkId, double> base;
  std::map<std::pair<LandmarkId, LandmarkId>, double> coupling;
  std::vector<LandmarkId> removed;
  std::vector<std::size_t> marginalize_calls;
};

/// Four old landmarks and one seen at step 99 (protected with P = 5 at step 100).
///   gains: 1: 0.10, 2: 0.20, 3: 0.50 (+0.5 once 1 is gone), 4: 1.00 (+1.0 once 2 is gone),
///          5: 0.05 (protected)
/// Greedy: 1 (d 0.1), 2 (0.2), 3 (1.0), 4 (2.0); D = 2, N = 5, lambda 0.4:
///   rho = 0.4, 0.35, 0.30, 0.46, ... -> drop 1 and 2 only.
ScriptedBackend handMade() {
  ScriptedBackend b({landmark(1, 1, 1, 0, 10), landmark(2, 1, 1, 0, 10), landmark(3, 1, 1, 0, 10),
                     landmark(4, 1, 1, 0, 10), landmark(5, 1, 1, 0, 99)});
  b.base = {{1, 0.10}, {2, 0.20}, {3, 0.50}, {4, 1.00}, {5, 0.05}};
  b.coupling = {{{3, 1}, 0.5}, {{4, 2}, 1.0}};
  return b;
}

MutualInformationOptions objective(double lambda = 0.4) {
  MutualInformationOptions o;
  o.mode = MutualInformationOptions::Mode::Objective;
  o.lambda = lambda;
  return o;
}

BudgetOptions noCap() {
  BudgetOptions o;
  o.max_landmarks.reset();  // [LandmarkBudget] max_landmarks = none
  return o;
}

}  // namespace

TEST(ActiveMinimization, ObjectiveValuesAndStopByHand) {
  const auto rho = objectiveValues({0.1, 0.2, 0.3, 2.0}, 10, 0.4);
  // rho_k = 0.6 d_k / 2 + 0.4 (10 - k) / 10.
  const std::vector<double> expected = {0.4, 0.39, 0.38, 0.37, 0.84};
  ASSERT_EQ(rho.size(), expected.size());
  for (std::size_t k = 0; k < rho.size(); ++k) EXPECT_NEAR(rho[k], expected[k], 1e-15);
  EXPECT_EQ(objectiveStop(rho), 3u);
  EXPECT_EQ(objectiveStop({0.4, 0.5}), 0u);       // first drop already increases rho
  EXPECT_EQ(objectiveStop({0.4, 0.4, 0.3}), 2u);  // equal is not an increase (Alg. 3 line 9)
  // No information anywhere (D = 0): rho falls with every drop, all go; negative round-off = 0.
  EXPECT_EQ(objectiveStop(objectiveValues({0, -1e-17, 0}, 3, 0.4)), 3u);
  EXPECT_EQ(objectiveStop(objectiveValues({}, 3, 0.4)), 0u);
  // lambda = 0: only accuracy counts, nothing goes unless d stays 0.
  EXPECT_EQ(objectiveStop(objectiveValues({0.1, 0.2}, 5, 0.0)), 0u);
  // lambda = 1: only memory counts, everything goes.
  EXPECT_EQ(objectiveStop(objectiveValues({0.1, 5.0, 0.2}, 5, 1.0)), 3u);
}

TEST(ActiveMinimization, GlobalMinimumLooksPastTheFirstIncrease) {
  // rho rises after the first drop, then falls below its start: first_increase keeps all,
  // global_minimum drops two.
  const std::vector<double> rho = {0.4, 0.5, 0.3, 0.35};
  EXPECT_EQ(objectiveStop(rho), 0u);
  EXPECT_EQ(objectiveMinimum(rho), 2u);
  EXPECT_EQ(objectiveMinimum({0.4, 0.3, 0.3}), 1u);  // the first of equal minima
  EXPECT_EQ(objectiveMinimum({0.4}), 0u);
  // Never fewer drops than the first-increase rule.
  const auto r = objectiveValues({0.1, 0.2, 0.3, 2.0}, 10, 0.4);
  EXPECT_EQ(objectiveMinimum(r), objectiveStop(r));
}

TEST(ActiveMinimization, HandMadeCaseDropsExactlyWhatTheObjectiveSays) {
  ScriptedBackend b = handMade();
  const auto scratch = [&] { return std::make_unique<ScriptedBackend>(b); };
  const ScheduleContext ctx{b, 100, true, scratch};
  const auto plan = activeMinimization(ctx, 0.4, 5, "objective");
  ASSERT_EQ(plan.drops.size(), 2u);
  EXPECT_EQ(plan.drops[0].id, 1);
  EXPECT_DOUBLE_EQ(plan.drops[0].score, 0.1);
  EXPECT_EQ(plan.drops[1].id, 2);
  EXPECT_DOUBLE_EQ(plan.drops[1].score, 0.2);
  EXPECT_TRUE(plan.marginalize_poses);
  EXPECT_EQ(plan.keep_last_poses, 5u);
  EXPECT_TRUE(b.removed.empty());  // the look-ahead ran on the copy

  // The full greedy sequence on a copy, by hand.
  ScriptedBackend copy = handMade();
  const auto seq = greedySequence(copy, {1, 2, 3, 4});
  ASSERT_EQ(seq.size(), 4u);
  EXPECT_EQ((std::vector<LandmarkId>{seq[0].id, seq[1].id, seq[2].id, seq[3].id}),
            (std::vector<LandmarkId>{1, 2, 3, 4}));
  EXPECT_DOUBLE_EQ(seq[2].gain, 1.0);
  EXPECT_DOUBLE_EQ(seq[3].gain, 2.0);

  // Without the coupling of 3 to 1, d_3 = 0.5 and rho_3 = 0.6 * 0.25 + 0.16 = 0.31 > 0.30: still
  // two; with lambda = 0.6, rho = 0.6, 0.5, 0.4, 0.44 -> again two; lambda = 0.9: 0.9, 0.725,
  // 0.56, 0.41, 0.2 -> all four.
  ScriptedBackend b9 = handMade();
  const auto scratch9 = [&] { return std::make_unique<ScriptedBackend>(b9); };
  EXPECT_EQ(activeMinimization({b9, 100, true, scratch9}, 0.9, 5, "objective").drops.size(), 4u);
}

TEST(ActiveMinimization, AgreesWithABruteForceEvaluationOnGaussianStates) {
  std::size_t interior = 0;  // cases where Alg. 3 stops strictly inside the sequence
  for (unsigned seed = 0; seed < 12; ++seed) {
    std::mt19937 rng(seed);
    auto state = budget_slam::testing::randomState(10, rng);
    // Landmarks 12 and 15 seen at step 98: protected with P = 5 at step 100.
    auto lms = state.landmarks();
    lms[2].last_step = 98;
    lms[5].last_step = 98;
    // Correlation strengths spread over three decades (weakly tied landmarks carry little
    // information), as in a filter that saw some landmarks once and others often.
    const Eigen::MatrixXd P0 = budget_slam::testing::randomSpd(23, rng);
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(23);
    std::uniform_real_distribution<double> u(-3, 0);
    for (int l = 0; l < 10; ++l) scale.segment<2>(3 + 2 * l).setConstant(std::pow(10.0, u(rng)));
    Eigen::MatrixXd Pc = scale.asDiagonal() * P0 * scale.asDiagonal();
    Pc.diagonal() = P0.diagonal();
    gaussian::GaussianStateBackend s(lms, Pc, 100);
    const double lambda = 0.2 + 0.06 * seed;

    // Brute force: full inverses of the reduced matrix at every greedy step.
    Eigen::MatrixXd P = s.covariance();
    std::vector<LandmarkId> ids;
    for (const auto& l : lms) ids.push_back(l.id);
    std::vector<LandmarkId> seq;
    std::vector<double> d;
    for (;;) {
      const auto g = budget_slam::testing::bruteForceGains(P);
      std::size_t best = ids.size();
      for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] == 12 || ids[i] == 15) continue;
        if (best == ids.size() || g[i] < g[best]) best = i;
      }
      if (best == ids.size()) break;
      seq.push_back(ids[best]);
      d.push_back(g[best]);
      P = budget_slam::testing::eraseBlock(P, 3 + 2 * best);
      ids.erase(ids.begin() + best);
    }
    ASSERT_EQ(seq.size(), 8u);
    const double D = *std::max_element(d.begin(), d.end());
    double prev = lambda;
    std::size_t k = 0;
    for (; k < d.size(); ++k) {
      const double rho = (1 - lambda) * d[k] / D + lambda * (10.0 - (k + 1)) / 10.0;
      if (rho > prev) break;
      prev = rho;
    }
    interior += k > 0 && k < d.size();

    const auto plan = activeMinimization({s, 100, true, {}}, lambda, 5, "objective");
    ASSERT_EQ(plan.drops.size(), k) << "seed " << seed;
    for (std::size_t i = 0; i < k; ++i) {
      EXPECT_EQ(plan.drops[i].id, seq[i]);
      EXPECT_NEAR(plan.drops[i].score, d[i], 1e-9);
    }
  }
  EXPECT_GE(interior, 3u);  // the cases exercise the stop, not only "none" or "all"
}

TEST(ActiveMinimization, BudgetManagerRunsObjectiveModeOnceAtTheEnd) {
  ScriptedBackend b = handMade();
  BudgetManager manager(noCap(), std::make_unique<MutualInformationReducer>(objective()));
  manager.setScratchFactory([](const Backend& x) {
    return std::make_unique<ScriptedBackend>(static_cast<const ScriptedBackend&>(x));
  });
  EXPECT_TRUE(manager.options().readmit_evicted);
  for (StepIndex s = 0; s <= 100; ++s) EXPECT_TRUE(manager.enforce(b, s).empty());
  const auto drops = manager.finish(b, 100);
  ASSERT_EQ(drops.size(), 2u);
  EXPECT_EQ(drops[0].id, 1);
  EXPECT_EQ(drops[1].id, 2);
  EXPECT_EQ(drops[0].reason, "objective");
  EXPECT_EQ(drops[0].n_before, 5u);
  EXPECT_EQ(drops[1].n_after, 3u);
  EXPECT_EQ(b.removed, (std::vector<LandmarkId>{1, 2}));
  EXPECT_EQ(b.marginalize_calls, (std::vector<std::size_t>{5}));
  EXPECT_EQ(manager.posesMarginalized(), 7u);
}

TEST(ActiveMinimization, BackendCloneIsTheDefaultLookAhead) {
  // No scratch factory: the manager looks ahead on Backend::clone().
  struct Copyable : ScriptedBackend {
    explicit Copyable(const ScriptedBackend& b) : ScriptedBackend(b) {}
    std::unique_ptr<Backend> clone() const override {
      ++clones;
      return std::make_unique<Copyable>(*this);
    }
    mutable int clones = 0;
  };
  Copyable b(handMade());
  BudgetManager manager(noCap(), std::make_unique<MutualInformationReducer>(objective()));
  for (StepIndex s = 0; s <= 100; ++s) EXPECT_TRUE(manager.enforce(b, s).empty());
  const auto drops = manager.finish(b, 100);
  ASSERT_EQ(drops.size(), 2u);
  EXPECT_EQ(drops[0].id, 1);
  EXPECT_EQ(drops[1].id, 2);
  EXPECT_GE(b.clones, 1);
  // Only the planned drops reached the real backend; the look-ahead removed all four candidates
  // from its copy.
  EXPECT_EQ(b.removed, (std::vector<LandmarkId>{1, 2}));
}

TEST(ActiveMinimization, WithoutAFaithfulLookAheadCopyItIsAConfigError) {
  // The fake's gains are not those of any joint covariance (it has none) and no scratch factory
  // is set.
  // It fails at the first step with landmarks, not after the run; same at the end.
  ScriptedBackend b = handMade();
  BudgetManager manager(noCap(), std::make_unique<MutualInformationReducer>(objective()));
  for (const bool at_end : {false, true}) {
    try {
      at_end ? manager.finish(b, 100) : manager.enforce(b, 0);
      FAIL() << at_end;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("[MutualInformationReducer] mode = objective needs"),
                std::string::npos)
          << e.what();
    }
  }
  // With no landmark yet there is nothing to check.
  ScriptedBackend empty(std::vector<LandmarkView>{});
  BudgetManager fresh(noCap(), std::make_unique<MutualInformationReducer>(objective()));
  EXPECT_TRUE(fresh.enforce(empty, 0).empty());
}

TEST(ActiveMinimization, IncrementalModeEveryPsiStepsAndNoReadmission) {
  MutualInformationOptions o = objective();
  o.mode = MutualInformationOptions::Mode::Incremental;
  o.psi = 3;
  o.pose_lag = 0;
  ScriptedBackend b(std::vector<LandmarkView>{});
  b.base = {};
  BudgetManager manager(noCap(), std::make_unique<MutualInformationReducer>(o));
  manager.setScratchFactory([](const Backend& x) {
    return std::make_unique<ScriptedBackend>(static_cast<const ScriptedBackend&>(x));
  });
  EXPECT_FALSE(manager.options().readmit_evicted);
  std::map<StepIndex, std::size_t> events;
  for (StepIndex s = 0; s < 9; ++s) {
    // One new landmark a step whose gain grows with its id: each minimization drops the oldest
    // ones while rho decreases.
    b.add(landmark(static_cast<LandmarkId>(s), 1, 1, s, s));
    b.base[static_cast<LandmarkId>(s)] = 0.1 * (s + 1) * (s + 1);
    const auto drops = manager.enforce(b, s);
    for (const auto& e : drops) EXPECT_EQ(e.reason, "incremental");
    if (!drops.empty()) events[s] = drops.size();
  }
  EXPECT_EQ(b.marginalize_calls.size(), 3u);  // after steps 2, 5 and 8
  for (const auto& [s, n] : events) EXPECT_TRUE(s == 2 || s == 5 || s == 8) << s;
  EXPECT_FALSE(events.empty());
  EXPECT_TRUE(manager.finish(b, 8).empty());  // incremental: nothing extra at the end
}

TEST(ActiveMinimization, IncrementalModeHoldsTheCapAfterItsOwnDrops) {
  // As above (Alg. 5 every 3 steps), with a cap of 3: after every step the map holds at most 3;
  // the scheduled drops of a minimization come first, then the cap with the cap-mode rule (the
  // lowest gain among the unprotected candidates).
  MutualInformationOptions o = objective();
  o.mode = MutualInformationOptions::Mode::Incremental;
  o.psi = 3;
  o.pose_lag = 0;
  BudgetOptions cap;
  cap.max_landmarks = 3;
  cap.protect_recent_steps = 1;
  ScriptedBackend b(std::vector<LandmarkView>{});
  BudgetManager manager(cap, std::make_unique<MutualInformationReducer>(o));
  manager.setScratchFactory([](const Backend& x) {
    return std::make_unique<ScriptedBackend>(static_cast<const ScriptedBackend&>(x));
  });
  EXPECT_TRUE(manager.capped());
  std::size_t scheduled = 0, over_cap = 0;
  for (StepIndex s = 0; s < 9; ++s) {
    // Two new landmarks a step; gains grow with the id, so the cap drops the oldest.
    for (const LandmarkId id : {LandmarkId(2 * s), LandmarkId(2 * s + 1)}) {
      b.add(landmark(id, 1, 1, s, s));
      b.base[id] = 0.1 * static_cast<double>((id + 1) * (id + 1));
    }
    const auto drops = manager.enforce(b, s);
    EXPECT_LE(b.landmarkCount(), 3u) << "step " << s;
    bool cap_started = false;
    for (const auto& e : drops) {
      if (e.reason == "incremental") {
        EXPECT_FALSE(cap_started) << "scheduled drops come first, step " << s;
        EXPECT_EQ((s + 1) % 3, 0u) << s;
        ++scheduled;
        continue;
      }
      cap_started = true;
      ++over_cap;
      EXPECT_EQ(e.reason, "over_cap") << s;
      // Cap-mode rule: the lowest gain among the landmarks not seen at this step.
      for (const auto& l : b.landmarks())
        if (l.last_step < s) EXPECT_LE(e.score, b.base.at(l.id)) << s;
    }
  }
  EXPECT_GT(scheduled, 0u);
  EXPECT_GT(over_cap, 0u);
  EXPECT_FALSE(manager.options().readmit_evicted);
  EXPECT_EQ(manager.evicted().size(), scheduled + over_cap);  // cap drops never return either
}

TEST(ActiveMinimization, CapModeSchedulesNothing) {
  ScriptedBackend b = handMade();
  MutualInformationOptions o;
  BudgetOptions cap;
  cap.max_landmarks = 5;  // the map's size: the cap does not bite
  BudgetManager manager(cap, std::make_unique<MutualInformationReducer>(o));
  EXPECT_TRUE(manager.enforce(b, 100).empty());
  EXPECT_TRUE(manager.finish(b, 100).empty());
  EXPECT_TRUE(b.marginalize_calls.empty());
}

TEST(ActiveMinimization, AStopRequestEndsTheGreedySequence) {
  // Ctrl-C during the end-of-run event: each greedy round (one information gain a candidate) is
  // seconds on a long run, so the sequence polls the stop request and ends at once.
  ScriptedBackend copy = handMade();
  budget_slam::Cancellation::request(SIGTERM);
  try {
    greedySequence(copy, {1, 2, 3, 4});
    ADD_FAILURE() << "no Interrupted";
  } catch (const budget_slam::Interrupted& e) {
    EXPECT_EQ(std::string(e.what()), "interrupted by SIGTERM");
  }
  budget_slam::Cancellation::clear();
  EXPECT_EQ(greedySequence(copy, {1, 2, 3, 4}).size(), 4u);
}
