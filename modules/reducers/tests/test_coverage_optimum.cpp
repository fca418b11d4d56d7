#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "FakeBackend.h"
#include "budget_slam/reducers/PlaceCoverageOptimum.h"
#include "budget_slam/reducers/PlaceCoverageReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

double coverageOf(const std::vector<std::vector<LandmarkId>>& places, const std::set<LandmarkId>& S,
                  std::size_t k) {
  double f = 0;
  for (const auto& p : places) {
    std::size_t n = 0;
    for (const LandmarkId id : p) n += S.count(id);
    f += static_cast<double>(std::min(n, k));
  }
  return f;
}

/// Best f over every subset of at most `budget` of landmarks 1..n.
double exhaustiveBest(const std::vector<std::vector<LandmarkId>>& places, std::size_t n,
                      std::size_t k, std::size_t budget) {
  double best = 0;
  for (std::uint32_t mask = 0; mask < (1u << n); ++mask) {
    if (static_cast<std::size_t>(__builtin_popcount(mask)) > budget) continue;
    std::set<LandmarkId> S;
    for (std::size_t i = 0; i < n; ++i)
      if (mask & (1u << i)) S.insert(static_cast<LandmarkId>(i + 1));
    best = std::max(best, coverageOf(places, S, k));
  }
  return best;
}

}  // namespace

TEST(PlaceCoverageOptimum, EqualsExhaustiveOptimumAndBoundsEveryReducer) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t n = 3 + rng() % 10;  // N <= 12
    const std::size_t n_places = 1 + rng() % 10;
    const std::size_t k = 1 + rng() % 3;
    const std::size_t budget = 1 + rng() % (n - 1);
    std::vector<std::vector<LandmarkId>> places(n_places);
    for (auto& p : places)
      for (LandmarkId id = 1; id <= n; ++id)
        if (rng() % 3 == 0) p.push_back(id);
    const PlaceCoverageOptimum opt = solvePlaceCoverageOptimum(places, k, budget);
    ASSERT_TRUE(opt.proven_optimal);
    EXPECT_DOUBLE_EQ(opt.coverage, exhaustiveBest(places, n, k, budget)) << "trial " << trial;
    EXPECT_LE(opt.selection.size(), budget);
    EXPECT_DOUBLE_EQ(coverageOf(places, {opt.selection.begin(), opt.selection.end()}, k),
                     opt.coverage);

    // The greedy place-coverage reducer and a random selection, both down to the budget, never
    // beat the bound.
    PlaceCoverageOptions o;
    o.min_landmarks = k;
    o.place_size = 1;
    o.heading_sectors = 1;
    PlaceCoverageReducer greedy(o);
    for (std::size_t p = 0; p < n_places; ++p) {
      StepObservation s;
      s.step = p;
      s.robot = Pose2(static_cast<double>(p) + 0.5, 0.5, 0);
      s.observed = places[p];
      greedy.observe(s);
    }
    FakeBackend backend({});
    std::vector<LandmarkView> views;
    for (LandmarkId id = 1; id <= n; ++id) views.push_back(landmark(id, 1, 1, 0, 0));
    while (views.size() > budget) {
      std::vector<std::size_t> all(views.size());
      for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
      const LandmarkId victim = greedy.choose({backend, views, all, 100}).id;
      greedy.forget(victim);
      views.erase(
          std::find_if(views.begin(), views.end(), [&](auto& v) { return v.id == victim; }));
    }
    EXPECT_LE(greedy.coverage(), opt.coverage + 1e-9);
    std::vector<LandmarkId> shuffled;
    for (LandmarkId id = 1; id <= n; ++id) shuffled.push_back(id);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    EXPECT_LE(coverageOf(places, {shuffled.begin(), shuffled.begin() + budget}, k),
              opt.coverage + 1e-9);
  }
}

TEST(PlaceCoverageOptimum, EverythingFitsAndSizeLimitIsAClearError) {
  const std::vector<std::vector<LandmarkId>> places = {{1, 2, 3}, {3, 4}, {}};
  const PlaceCoverageOptimum all = solvePlaceCoverageOptimum(places, 2, 10);
  EXPECT_DOUBLE_EQ(all.coverage, 4.0);
  EXPECT_EQ(all.selection, (std::vector<LandmarkId>{1, 2, 3, 4}));
  // One landmark: 3 covers one of place 0's two and one of place 1's.
  EXPECT_DOUBLE_EQ(solvePlaceCoverageOptimum(places, 2, 1).coverage, 2.0);
  PlaceCoverageOptimumLimits small;
  small.max_sightings = 4;
  try {
    solvePlaceCoverageOptimum(places, 2, 1, small);
    FAIL();
  } catch (const std::length_error& e) {
    EXPECT_STREQ(e.what(),
                 "offline optimum: more than 4 (place, landmark) sightings; the integer program "
                 "is too large");
  }
}
