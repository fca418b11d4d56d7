#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <numeric>

#include "FakeBackend.h"
#include "TestStates.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/MutualInformationReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::bruteForceGain;
using budget_slam::testing::bruteForceGains;
using budget_slam::testing::eraseBlock;
using budget_slam::testing::randomState;

namespace {
std::vector<std::size_t> all(std::size_t n) {
  std::vector<std::size_t> v(n);
  std::iota(v.begin(), v.end(), 0);
  return v;
}
}  // namespace

TEST(MutualInformationReducer, ScoresEqualBruteForceOnRandomSpdStates) {
  std::mt19937 rng(3);
  MutualInformationReducer mi{MutualInformationOptions()};
  for (int n : {1, 2, 5, 17, 40}) {
    auto state = randomState(n, rng);
    const auto lms = state.landmarks();
    std::vector<LandmarkId> ids;
    for (const auto& l : lms) ids.push_back(l.id);
    const auto brute = bruteForceGains(state.covariance());
    const auto gains = state.informationGain(ids);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(gains[i], brute[i], 1e-9) << n << " " << i;
    const auto c = mi.choose({state, lms, all(n), 100});
    const auto lowest = std::min_element(brute.begin(), brute.end()) - brute.begin();
    EXPECT_EQ(c.id, lms[lowest].id);
    EXPECT_NEAR(c.score, brute[lowest], 1e-9);
  }
}

TEST(MutualInformationReducer, SuccessiveDropsOfOneEventEqualAFreshComputation) {
  std::mt19937 rng(8);
  auto state = randomState(30, rng);
  Eigen::MatrixXd P = state.covariance();
  std::vector<LandmarkId> order;
  for (const auto& l : state.landmarks()) order.push_back(l.id);

  BudgetOptions o;
  o.max_landmarks = 22;  // one event, eight drops
  o.protect_recent_steps = 0;
  BudgetManager manager(o, std::make_unique<MutualInformationReducer>(MutualInformationOptions()));
  const auto drops = manager.enforce(state, 100);
  ASSERT_EQ(drops.size(), 8u);
  for (const auto& e : drops) {
    // Fresh brute force on the reduced matrix: the victim is its least informative landmark
    // and the logged score its gain.
    const auto brute = bruteForceGains(P);
    const auto lowest = std::min_element(brute.begin(), brute.end()) - brute.begin();
    EXPECT_EQ(e.id, order[lowest]);
    EXPECT_NEAR(e.score, brute[lowest], 1e-9);
    EXPECT_EQ(e.reason, "over_cap");
    P = eraseBlock(P, 3 + 2 * lowest);
    order.erase(order.begin() + lowest);
  }
  // The gains the backend serves after the event (Schur-updated) match the last fresh ones.
  const auto after = state.informationGain(order);
  const auto brute = bruteForceGains(P);
  for (std::size_t i = 0; i < order.size(); ++i) EXPECT_NEAR(after[i], brute[i], 1e-9);
}

TEST(MutualInformationReducer, TiesGoToTheLowestId) {
  budget_slam::testing::FakeBackend b({budget_slam::testing::landmark(9, 1, 1, 0, 0),
                                       budget_slam::testing::landmark(4, 1, 1, 0, 0),
                                       budget_slam::testing::landmark(6, 1, 1, 0, 0)});
  b.gains = {{9, 0.5}, {4, 0.5}, {6, 0.7}};
  MutualInformationReducer mi{MutualInformationOptions()};
  const auto lms = b.landmarks();
  const auto c = mi.choose({b, lms, all(3), 10});
  EXPECT_EQ(c.id, 4);
  EXPECT_DOUBLE_EQ(c.score, 0.5);
  EXPECT_EQ(mi.choose({b, lms, {0, 2}, 10}).id, 9);
}

TEST(MutualInformationReducer, RegisteredWithItsSectionAndKeys) {
  const auto& e = builtinReducers().entry("mi");
  ASSERT_EQ(e.sections.size(), 1u);
  EXPECT_EQ(e.sections[0].name, "MutualInformationReducer");
  EXPECT_EQ(e.sections[0].keys(),
            (std::vector<std::string>{"mode", "lambda", "psi", "pose_lag", "stop"}));
  mrpt::config::CConfigFileMemory ini;
  ini.write("MutualInformationReducer", "mode", "incremental");
  ini.write("MutualInformationReducer", "psi", "30");
  auto r = builtinReducers().create("mi", ini, 1);
  auto* mi = dynamic_cast<MutualInformationReducer*>(r.get());
  ASSERT_NE(mi, nullptr);
  EXPECT_EQ(mi->options().mode, MutualInformationOptions::Mode::Incremental);
  EXPECT_EQ(mi->options().psi, 30u);
  ASSERT_EQ(dropScheduler(r.get()), mi);
  EXPECT_FALSE(mi->readmitsEvicted());
  EXPECT_TRUE(mi->decidesMapSize());
}
