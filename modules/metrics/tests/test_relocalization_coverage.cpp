// Relocalization coverage (docs/OUTPUTS.md "Relocalization coverage") on cases counted by hand.
#include <gtest/gtest.h>

#include <random>

#include "budget_slam/metrics/LocalizationScore.h"
#include "budget_slam/metrics/MappedArea.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"

using namespace budget_slam;
using namespace budget_slam::metrics;

namespace {
/// Three places: A sees landmarks 1-3, B 4-6, C 7-9.
const std::vector<LandmarkId> kA = {1, 2, 3}, kB = {4, 5, 6}, kC = {7, 8, 9};
}  // namespace

// The run A x4, B x3, C x5, A x2 under a cap of 6 that drops the oldest landmarks: C drives A
// out, A's return drives B out. Every number below is counted by hand.
TEST(RelocalizationTracker, ThreePlacesCountedByHand) {
  RelocalizationTracker t(2);
  std::vector<double> so_far;
  const auto step = [&](StepIndex k, const std::vector<LandmarkId>& seen) {
    for (LandmarkId id : seen) t.landmarkAdded(id);
    return seen;
  };
  StepIndex k = 0;
  for (int i = 0; i < 4; ++i, ++k)
    t.addStep(k, step(k, kA)), so_far.push_back(t.coverageSoFarPct());
  for (int i = 0; i < 3; ++i, ++k)
    t.addStep(k, step(k, kB)), so_far.push_back(t.coverageSoFarPct());
  for (int i = 0; i < 5; ++i, ++k) {
    step(k, kC);
    if (i == 0)
      for (LandmarkId id : kA) t.landmarkRemoved(id);
    EXPECT_EQ(t.addStep(k, kC), 3u);
    so_far.push_back(t.coverageSoFarPct());
  }
  for (int i = 0; i < 2; ++i, ++k) {
    step(k, kA);
    if (i == 0)
      for (LandmarkId id : kB) t.landmarkRemoved(id);
    t.addStep(k, kA);
    so_far.push_back(t.coverageSoFarPct());
  }
  // Steps 0-6: everything seen is held. Step 7: A's 4 steps lost, 4 of 8 covered. Step 11: 8 of
  // 12. Step 12: A back (same ids), B out: 10 of 13; step 13: 11 of 14.
  for (int i = 0; i < 7; ++i) EXPECT_DOUBLE_EQ(so_far[i], 100.0) << i;
  EXPECT_DOUBLE_EQ(so_far[7], 50.0);
  EXPECT_DOUBLE_EQ(so_far[11], 100.0 * 8 / 12);
  EXPECT_DOUBLE_EQ(so_far[12], 100.0 * 10 / 13);
  EXPECT_DOUBLE_EQ(so_far[13], 100.0 * 11 / 14);

  const auto c = t.coverage();
  EXPECT_EQ(c.steps, 14u);
  EXPECT_EQ(c.steps_covered, 11u);
  EXPECT_DOUBLE_EQ(c.coverage_pct, 100.0 * 11 / 14);
  EXPECT_DOUBLE_EQ(c.mean_landmarks, 33.0 / 14);  // 6 A steps and 5 C steps see 3 each
  EXPECT_FALSE(c.sampled);

  // The same numbers recomputed from the kept steps against the final map.
  auto steps = t.steps();
  const std::set<LandmarkId> final_map = {1, 2, 3, 7, 8, 9};
  const auto again = coverageOf(
      steps, [&](LandmarkId id) { return final_map.count(id) > 0; }, 2);
  EXPECT_EQ(again.steps_covered, 11u);
  EXPECT_DOUBLE_EQ(again.mean_landmarks, c.mean_landmarks);
  for (std::size_t i = 0; i < steps.size(); ++i)
    EXPECT_EQ(steps[i].in_map, t.steps()[i].in_map) << i;

  // k = 4: no step sees four map landmarks.
  EXPECT_EQ(coverageOf(
                steps, [&](LandmarkId id) { return final_map.count(id) > 0; }, 4)
                .steps_covered,
            0u);
}

TEST(RelocalizationTracker, DuplicatesAndMissingIdsAreNotCounted) {
  RelocalizationTracker t(2);
  t.landmarkAdded(5);
  t.landmarkAdded(5);
  EXPECT_EQ(t.addStep(0, {5, 5, kNoLandmarkId, 6}), 1u);
  t.landmarkAdded(6);
  EXPECT_EQ(t.steps()[0].in_map, 2u);
  EXPECT_DOUBLE_EQ(t.coverageSoFarPct(), 100.0);
  t.landmarkRemoved(6);
  t.landmarkRemoved(6);
  EXPECT_DOUBLE_EQ(t.coverageSoFarPct(), 0.0);
  EXPECT_TRUE(std::isnan(RelocalizationTracker().coverageSoFarPct()));
}

// Bounded memory: at most max_samples steps are kept, evenly spread, and the incremental counts
// equal a recomputation over the kept steps whatever the drops.
TEST(RelocalizationTracker, SampledTrackerStaysBoundedAndConsistent) {
  RelocalizationTracker t(2, 64);
  std::mt19937 rng(7);
  std::set<LandmarkId> map;
  for (StepIndex k = 0; k < 5000; ++k) {
    std::vector<LandmarkId> seen;
    for (int r = 0; r < 4; ++r) seen.push_back(static_cast<LandmarkId>((k / 10 + r) % 300));
    for (LandmarkId id : seen) t.landmarkAdded(id), map.insert(id);
    while (map.size() > 40) {  // drop a random one
      auto it = map.begin();
      std::advance(it, rng() % map.size());
      t.landmarkRemoved(*it);
      map.erase(it);
    }
    t.addStep(k, seen);
    ASSERT_LE(t.steps().size(), 64u);
  }
  EXPECT_TRUE(t.sampled());
  EXPECT_GE(t.steps().size(), 32u);
  const StepIndex stride = t.steps()[1].step - t.steps()[0].step;
  for (std::size_t i = 1; i < t.steps().size(); ++i)
    EXPECT_EQ(t.steps()[i].step - t.steps()[i - 1].step, stride);
  auto steps = t.steps();
  const auto again = coverageOf(
      steps, [&](LandmarkId id) { return map.count(id) > 0; }, 2, true);
  const auto c = t.coverage();
  EXPECT_EQ(again.steps_covered, c.steps_covered);
  EXPECT_DOUBLE_EQ(again.mean_landmarks, c.mean_landmarks);
  EXPECT_TRUE(c.sampled);
}

TEST(MatchLandmarks, PairsOneToOneByMahalanobisDistance) {
  const auto lm = [](LandmarkId id, double x, double y, double var) {
    LandmarkView l;
    l.id = id;
    l.mean = Eigen::Vector2d(x, y);
    l.cov = var * Eigen::Matrix2d::Identity();
    return l;
  };
  // Reference: 100 at the origin, 101 at (1, 0), 102 far away. Map: 7 near 101, 8 near 100 and
  // a little nearer 101 than 7 is (greedy: 8 takes 100, its best free one after 7 takes 101), 9
  // nowhere near anything.
  const std::vector<LandmarkView> ref = {lm(100, 0, 0, 0.01), lm(101, 1, 0, 0.01),
                                         lm(102, 50, 50, 0.01)};
  const std::vector<LandmarkView> map = {lm(7, 1.02, 0, 0.01), lm(8, 0.05, 0, 0.01),
                                         lm(9, 20, 0, 0.01)};
  const auto m = matchLandmarks(map, ref, 13.8);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.at(7), 101);
  EXPECT_EQ(m.at(8), 100);
  // A map equal to the reference pairs with itself.
  const auto self = matchLandmarks(ref, ref, 13.8);
  ASSERT_EQ(self.size(), 3u);
  for (const auto& [a, b] : self) EXPECT_EQ(a, b);
  // Two landmarks competing for one: only the nearer gets it.
  const auto one =
      matchLandmarks({lm(1, 0.1, 0, 0.01), lm(2, 0.02, 0, 0.01)}, {lm(100, 0, 0, 0.01)}, 13.8);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.at(2), 100);
}

TEST(LocalizationScorer, CountsLostStepsAndErrors) {
  LocalizationScorer s(1.0, 2);
  EXPECT_FALSE(s.add(0.3, 3, 2.0));
  EXPECT_FALSE(s.add(0.4, 2, 4.0));
  EXPECT_TRUE(s.add(1.2, 1, std::nan("")));
  EXPECT_FALSE(s.add(std::nan(""), 0, std::nan("")));  // nothing to compare with
  EXPECT_TRUE(s.add(std::numeric_limits<double>::infinity(), 0, std::nan("")));  // diverged
  const auto r = s.score();
  EXPECT_EQ(r.steps, 5u);
  EXPECT_EQ(r.compared, 4u);
  EXPECT_EQ(r.lost, 2u);
  EXPECT_DOUBLE_EQ(r.lost_pct, 50.0);
  EXPECT_DOUBLE_EQ(r.rmse_m, std::sqrt((0.09 + 0.16 + 1.44) / 3));
  EXPECT_DOUBLE_EQ(r.max_m, 1.2);
  EXPECT_DOUBLE_EQ(r.coverage_pct, 40.0);
  EXPECT_DOUBLE_EQ(r.mean_landmarks, 6.0 / 5);
  EXPECT_DOUBLE_EQ(r.nees_mean, 3.0);
  EXPECT_EQ(r.nees_samples, 2u);
}

TEST(LocalizationScorer, ScoresOnlyTheMappedAreaAndSuccessPerPlace) {
  // Thresholds 0.25 m and 5 deg. Place A: 3 steps, 2 tracked (one has a 10 deg yaw error);
  // place B: 1 step, tracked; one step outside the mapped area counts for nothing but
  // `compared`, whatever its error.
  LocalizationScorer s(1.0, 2, 0.25, 5 * M_PI / 180);
  const PlaceKey a{0, 0, 0}, b{5, 0, 1};
  const auto step = [](double e, double yaw_deg, bool in, std::optional<PlaceKey> p) {
    StepError x;
    x.error_m = e;
    x.yaw_error = yaw_deg * M_PI / 180;
    x.map_landmarks = 2;
    x.in_mapped_area = in;
    x.place = p;
    return x;
  };
  EXPECT_FALSE(s.add(step(0.1, 1, true, a)));
  EXPECT_FALSE(s.add(step(0.2, 10, true, a)));
  EXPECT_FALSE(s.add(step(0.24, 4.9, true, a)));
  EXPECT_FALSE(s.add(step(0.05, 0, true, b)));
  EXPECT_FALSE(s.add(step(50, 0, false, b)));  // outside: not lost, not in the errors
  const auto r = s.score();
  EXPECT_EQ(r.compared, 5u);
  EXPECT_EQ(r.scored, 4u);
  EXPECT_DOUBLE_EQ(r.scored_pct, 80.0);
  EXPECT_EQ(r.places, 2u);
  EXPECT_DOUBLE_EQ(r.success_pct, 100.0 * (2.0 / 3 + 1.0) / 2);
  EXPECT_DOUBLE_EQ(r.max_m, 0.24);
  EXPECT_DOUBLE_EQ(r.lost_pct, 0.0);
  EXPECT_TRUE(s.tracked(0.25, 5 * M_PI / 180));
  EXPECT_FALSE(s.tracked(std::numeric_limits<double>::infinity(), 0));  // a diverged filter
}

TEST(MappedArea, CellsWithinReachOfThePath) {
  const MappedArea area({{0.5, 0.5, 0}, {2.5, 0.5, 1}}, 1.0, 0.8);  // cells (0, 0), (2, 0), 1 round
  EXPECT_TRUE(area.contains(0.5, 0.5));
  EXPECT_TRUE(area.contains(-0.5, 1.5));  // a neighbour of (0, 0)
  EXPECT_TRUE(area.contains(3.9, -0.9));  // a neighbour of (2, 0)
  EXPECT_FALSE(area.contains(4.1, 0.5));  // two cells away
  EXPECT_FALSE(area.contains(0.5, -1.1));
  EXPECT_TRUE(MappedArea().contains(1e6, -1e6));     // no path known: everywhere
  const MappedArea wide({{0.5, 0.5, 0}}, 1.0, 2.5);  // three cells round (0, 0)
  EXPECT_TRUE(wide.contains(3.9, -2.9));
  EXPECT_FALSE(wide.contains(4.1, 0.5));
  EXPECT_TRUE(MappedArea({{0.5, 0.5, 0}}, 1.0, 0).contains(0.9, 0.1));  // reach 0: its own cell
  EXPECT_FALSE(MappedArea({{0.5, 0.5, 0}}, 1.0, 0).contains(1.1, 0.1));
}
