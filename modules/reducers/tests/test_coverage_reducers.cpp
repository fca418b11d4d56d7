#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <numeric>
#include <set>

#include "FakeBackend.h"
#include "TestStates.h"
#include "budget_slam/reducers/BaselineReducers.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/CoverageSelection.h"
#include "budget_slam/reducers/InformationContent.h"
#include "budget_slam/reducers/ViewClusterReducers.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

std::vector<std::size_t> all(std::size_t n) {
  std::vector<std::size_t> v(n);
  std::iota(v.begin(), v.end(), 0);
  return v;
}

ReducerChoice ask(Reducer& r, const FakeBackend& b, std::vector<std::size_t> candidates,
                  StepIndex step = 100) {
  const auto lms = b.landmarks();
  return r.choose({b, lms, candidates, step});
}

/// Hochdorfer & Schlegel Fig. 1. Room 1 (observed from around (2, 2)): six well-known landmarks,
/// sigma^2 from 0.01 to 0.06 m^2 (I from 33 to 200 1/m^2). Room 2 (observed from around (30, 2)):
/// three uncertain ones, sigma^2 0.5 to 1 m^2 (I from 2 to 4). N = 9: k = round(2.25) = 2.
FakeBackend twoRooms() {
  FakeBackend b({});
  const double room1[] = {0.01, 0.02, 0.03, 0.04, 0.05, 0.06};
  for (int i = 0; i < 6; ++i)
    b.add(landmark(1 + i, room1[i], room1[i], 0, 10, 1.0 + 0.4 * i, 2.0 + 0.3 * (i % 2)));
  const double room2[] = {0.5, 0.7, 1.0};
  for (int i = 0; i < 3; ++i)
    b.add(landmark(7 + i, room2[i], room2[i], 20, 30, 30.0 + 0.5 * i, 2.0 - 0.3 * i));
  return b;
}

CoverageOptions defaults() { return CoverageOptions(); }

}  // namespace

TEST(ViewClusterReducer, TwoRoomsCoverageDropsFromTheWellKnownRoom) {
  FakeBackend b = twoRooms();
  const auto lms = b.landmarks();
  // The clusters are the rooms.
  const auto clusters = coverageClusters(lms, defaults());
  ASSERT_EQ(clusters.centres.size(), 2u);
  for (int i = 1; i < 6; ++i) EXPECT_EQ(clusters.label[i], clusters.label[0]);
  for (int i = 7; i < 9; ++i) EXPECT_EQ(clusters.label[i], clusters.label[6]);
  EXPECT_NE(clusters.label[0], clusters.label[6]);

  ViewClusterReducer coverage(defaults());
  InfoContentReducer info;
  const auto c = ask(coverage, b, all(9));
  const auto i = ask(info, b, all(9));
  // Room 1 spread 200 - 33.3 = 166.7 > room 2 spread 4 - 2 = 2: room 1's lowest I (id 6, 1/0.06
  // + 1/0.06) goes; info-content takes the globally lowest I, id 9 in room 2 (I = 2).
  EXPECT_EQ(c.id, 6);
  EXPECT_NEAR(c.score, 2 / 0.06, 1e-9);
  EXPECT_EQ(i.id, 9);
  EXPECT_NEAR(i.score, 2.0, 1e-12);

  // Dropping one by one down to five (k stays 2 for N >= 6): room 1 gives up its landmarks in
  // increasing I while room 2 keeps all three.
  ViewClusterReducer again(defaults());
  std::vector<LandmarkId> dropped;
  while (b.landmarkCount() > 5) {
    const auto v = ask(again, b, all(b.landmarkCount()));
    dropped.push_back(v.id);
    b.removeLandmark(v.id);
  }
  EXPECT_EQ(dropped, (std::vector<LandmarkId>{6, 5, 4, 3}));
}

TEST(ViewClusterReducer, ClustersWithoutCandidatesAreSkippedAndProtectedMembersCountInSpread) {
  FakeBackend b = twoRooms();
  ViewClusterReducer coverage(defaults());
  // Only room 2 may go: its lowest I, id 9.
  EXPECT_EQ(ask(coverage, b, {6, 7, 8}).id, 9);
  // Room 1 with only id 1 (I = 200) as a candidate: spread is over all members (166.7), so room
  // 1 still wins and its only candidate goes, though it is the best landmark of the map.
  EXPECT_EQ(ask(coverage, b, {0, 6, 7, 8}).id, 1);
}

TEST(ViewClusterReducer, SingletonClustersFallBackToLowestInformationThenLowestId) {
  // ratio 1: every landmark its own cluster, every spread 0 -> lowest I overall, then lowest id.
  mrpt::config::CConfigFileMemory ini;
  ini.write("CoverageReducer", "cluster_ratio", "1.0");
  auto r = builtinReducers().create("coverage", ini, 3);
  FakeBackend b({landmark(4, 0.5, 0.5, 0, 0, 0, 0), landmark(2, 0.5, 0.5, 0, 0, 10, 0),
                 landmark(3, 0.1, 0.1, 0, 0, 20, 0)});
  const auto c = ask(*r, b, all(3));
  EXPECT_EQ(c.id, 2);
  EXPECT_DOUBLE_EQ(c.score, 4.0);
}

TEST(ViewClusterReducer, EqualSpreadsGoToTheLowerInformationPick) {
  // Two far clusters (k = 2) whose spreads are both exactly 16 1/m^2 (variances are powers of
  // two): the tie goes to the cluster whose pick has the lower I.
  CoverageOptions o;
  o.cluster_ratio = 0.5;  // k = 2
  ViewClusterReducer r(o);
  const FakeBackend low_b({landmark(1, 1 / 32.0, 0.5, 0, 0, 0, 0),       // I = 34
                           landmark(2, 1 / 16.0, 0.5, 0, 0, 0.1, 0),     // I = 18
                           landmark(3, 1.0, 1.0, 0, 0, 50, 0),           // I = 2
                           landmark(4, 1 / 16.0, 0.5, 0, 0, 50.1, 0)});  // I = 18
  EXPECT_EQ(ask(r, low_b, all(4)).id, 3);
  const FakeBackend low_a({landmark(1, 1 / 32.0, 0.5, 0, 0, 0, 0),         // I = 34
                           landmark(2, 1 / 16.0, 0.5, 0, 0, 0.1, 0),       // I = 18
                           landmark(3, 1 / 32.0, 0.125, 0, 0, 50, 0),      // I = 40
                           landmark(4, 1 / 16.0, 0.125, 0, 0, 50.1, 0)});  // I = 24
  EXPECT_EQ(ask(r, low_a, all(4)).id, 2);
}

TEST(ViewClusterReducer, SameSeedSameChoiceAndSeedComesFromTheRunUnlessSet) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 40), v(0.01, 1);
  FakeBackend b({});
  for (int i = 0; i < 60; ++i) b.add(landmark(i, v(rng), v(rng), 0, 0, u(rng), u(rng)));
  mrpt::config::CConfigFileMemory ini;
  auto a1 = builtinReducers().create("coverage", ini, 11);
  auto a2 = builtinReducers().create("coverage", ini, 11);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(ask(*a1, b, all(60)).id, ask(*a2, b, all(60)).id);
  std::ostringstream dump;
  a1->dumpOptions(dump);
  EXPECT_NE(dump.str().find("seed                     = 11"), std::string::npos);
  ini.write("CoverageReducer", "seed", "5");
  std::ostringstream dump2;
  builtinReducers().create("coverage", ini, 11)->dumpOptions(dump2);
  EXPECT_NE(dump2.str().find("seed                     = 5"), std::string::npos);
}

TEST(ViewClusterGainReducer, TwoRoomsByInformationGain) {
  FakeBackend b = twoRooms();
  // Room 1 gains 6, 5.5, 5, 4.8, 4.6, 1.0 bits; room 2: 0.3, 0.8, 0.9.
  const double g[] = {6, 5.5, 5, 4.8, 4.6, 1.0, 0.3, 0.8, 0.9};
  for (int i = 0; i < 9; ++i) b.gains[1 + i] = g[i];
  ViewClusterGainReducer r(defaults());
  // Room 1 spread 6 - 1 = 5 > room 2: 0.9 - 0.3 = 0.6.
  const auto c = ask(r, b, all(9));
  EXPECT_EQ(c.id, 6);
  EXPECT_DOUBLE_EQ(c.score, 1.0);
  // Spread is best member minus worst *candidate*: with id 1 (6 bits) protected and only 2..6
  // candidates the room-1 spread stays 6 - 1 = 5; with only id 1 a candidate it is 6 - 6 = 0 and
  // room 2 (0.6) wins.
  EXPECT_EQ(ask(r, b, {1, 2, 3, 4, 5, 6, 7, 8}).id, 6);
  EXPECT_EQ(ask(r, b, {0, 6, 7, 8}).id, 7);
  // The Hochdorfer spread (Members) would keep picking room 1 there (6 - 1 = 5 > 0.6).
  const auto lms = b.landmarks();
  const std::vector<std::size_t> cand = {0, 6, 7, 8};
  const DropContext ctx{b, lms, cand, 100};
  const auto clusters = coverageClusters(lms, defaults());
  EXPECT_EQ(
      pickByClusterSpread(ctx, clusters.label, std::vector<double>(g, g + 9), Spread::Members).id,
      1);
}

TEST(ViewClusterGainReducer, DisagreesWithCoverageWhenDiagonalInformationMisleads) {
  // Same room, five landmarks. Id 1 has the smallest variances (highest I) but is nearly
  // uncorrelated with the rest (0.05 bits); id 5 is uncertain but carries 3 bits.
  FakeBackend b({landmark(1, 0.01, 0.01, 0, 0, 0, 0), landmark(2, 0.1, 0.1, 0, 0, 0.1, 0),
                 landmark(3, 0.1, 0.1, 0, 0, 0.2, 0), landmark(4, 0.2, 0.2, 0, 0, 0.3, 0),
                 landmark(5, 0.9, 0.9, 0, 0, 0.4, 0)});
  b.gains = {{1, 0.05}, {2, 1.0}, {3, 1.2}, {4, 2.0}, {5, 3.0}};
  ViewClusterReducer cov(defaults());
  ViewClusterGainReducer covmi(defaults());
  EXPECT_EQ(ask(cov, b, all(5)).id, 5);
  EXPECT_EQ(ask(covmi, b, all(5)).id, 1);
}

TEST(ViewClusterGainReducer, ScoreIsTheBackendsGainOnARealGaussianState) {
  std::mt19937 rng(21);
  auto state = budget_slam::testing::randomState(40, rng);
  const auto lms = state.landmarks();
  const auto cand = all(40);
  ViewClusterGainReducer r(defaults());
  const auto c = r.choose({state, lms, cand, 100});
  const auto brute = budget_slam::testing::bruteForceGains(state.covariance());
  std::size_t idx = 0;
  while (lms[idx].id != c.id) ++idx;
  EXPECT_NEAR(c.score, brute[idx], 1e-9);
  // And it is the lowest-gain member of its cluster.
  const auto clusters = coverageClusters(lms, defaults());
  for (std::size_t i = 0; i < lms.size(); ++i)
    if (clusters.label[i] == clusters.label[idx]) EXPECT_GE(brute[i], brute[idx] - 1e-9);
}
