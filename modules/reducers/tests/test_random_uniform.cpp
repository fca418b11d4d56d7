// `random` chooses uniformly: Pearson's chi-squared over many draws on a fixed candidate set, for
// both draws (a fresh draw each drop; one fixed score a landmark, over many seeds).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <map>
#include <numeric>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BaselineReducers.h"
#include "budget_slam/reducers/BuiltinReducers.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

/// The upper 0.1% point of the chi-squared distribution with 9 degrees of freedom (10 cells).
constexpr double kChi2Df9At001 = 27.877;

/// Pearson's statistic of `counts` against equal expected counts.
double chiSquared(const std::map<LandmarkId, int>& counts, std::size_t cells, int draws) {
  const double expected = static_cast<double>(draws) / static_cast<double>(cells);
  double chi2 = 0;
  std::size_t seen = 0;
  for (const auto& [id, n] : counts) chi2 += (n - expected) * (n - expected) / expected, ++seen;
  chi2 += static_cast<double>(cells - seen) * expected;  // cells never drawn
  return chi2;
}

/// Ten landmarks with scattered ids, all candidates.
struct TenCandidates {
  std::vector<LandmarkView> lms;
  std::vector<std::size_t> all;
  TenCandidates() {
    for (const LandmarkId id : {3, 17, 4, 250, 99, 1000, 8, 41, 42, 7})
      lms.push_back(landmark(id, 1, 1, 0, 0));
    all.resize(lms.size());
    std::iota(all.begin(), all.end(), 0);
  }
};

}  // namespace

TEST(RandomUniform, ChiSquaredTestDetectsABiasedChooser) {
  // The instrument itself: one candidate drawn 20% more often than its share is caught.
  std::map<LandmarkId, int> biased;
  const int draws = 100000;
  for (LandmarkId id = 0; id < 10; ++id) biased[id] = id == 0 ? 12000 : (draws - 12000) / 9;
  EXPECT_GT(chiSquared(biased, 10, draws), kChi2Df9At001);
}

TEST(RandomUniform, EachDropDrawsUniformlyAmongTheCandidates) {
  const TenCandidates c;
  FakeBackend b(c.lms);
  RandomReducer r(2024);
  std::map<LandmarkId, int> counts;
  const int draws = 100000;
  for (int k = 0; k < draws; ++k) ++counts[r.choose({b, c.lms, c.all, 1}).id];
  EXPECT_EQ(counts.size(), 10u);
  EXPECT_LT(chiSquared(counts, 10, draws), kChi2Df9At001);
}

TEST(RandomUniform, PerLandmarkScoresChooseUniformlyOverSeedsAndConsistentlyWithinOne) {
  const TenCandidates c;
  FakeBackend b(c.lms);
  RandomOptions o;
  o.draw = RandomOptions::Draw::PerLandmark;
  std::map<LandmarkId, int> counts;
  const int seeds = 50000;
  for (int seed = 1; seed <= seeds; ++seed) {
    RandomReducer r(static_cast<std::uint64_t>(seed), o);
    const LandmarkId first = r.choose({b, c.lms, c.all, 1}).id;
    // One seed, one ranking: asked again, or with the candidates in another order, the same one.
    std::vector<std::size_t> reversed(c.all.rbegin(), c.all.rend());
    ASSERT_EQ(r.choose({b, c.lms, reversed, 2}).id, first);
    ++counts[first];
  }
  EXPECT_EQ(counts.size(), 10u);
  EXPECT_LT(chiSquared(counts, 10, seeds), kChi2Df9At001);
  // The lowest score goes: drop it and the next lowest of the rest goes.
  RandomReducer r(7, o);
  const LandmarkId first = r.choose({b, c.lms, c.all, 1}).id;
  std::vector<std::size_t> rest;
  for (std::size_t i = 0; i < c.lms.size(); ++i)
    if (c.lms[i].id != first) rest.push_back(i);
  const auto second = r.choose({b, c.lms, rest, 1});
  EXPECT_GT(second.score, RandomReducer::landmarkScore(7, first));
  for (const std::size_t i : rest)
    EXPECT_GE(RandomReducer::landmarkScore(7, c.lms[i].id), second.score);
}

TEST(RandomUniform, DrawIsAnOptionOfTheRegisteredReducer) {
  const TenCandidates c;
  FakeBackend b(c.lms);
  mrpt::config::CConfigFileMemory ini;
  ini.write("RandomReducer", "draw", "per_landmark");
  auto r = builtinReducers().create("random", ini, 5);
  const auto choice = r->choose({b, c.lms, c.all, 1});
  EXPECT_DOUBLE_EQ(choice.score, RandomReducer::landmarkScore(5, choice.id));
  ini.write("RandomReducer", "draw", "sometimes");
  try {
    builtinReducers().entry("random").validate(ini);
    FAIL() << "a bad draw passed";
  } catch (const KeyError& e) {
    EXPECT_EQ(e.section(), "RandomReducer");
    EXPECT_EQ(e.key(), "draw");
  }
}
