#include <gtest/gtest.h>

#include <numeric>
#include <set>

#include "FakeBackend.h"
#include "budget_slam/reducers/BaselineReducers.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {
ReducerChoice ask(Reducer& r, const std::vector<LandmarkView>& lms,
                  std::vector<std::size_t> candidates) {
  FakeBackend b(lms);
  return r.choose({b, lms, candidates, 100});
}
}  // namespace

TEST(OldestReducer, FirstSeenEarliestTiesToLowestId) {
  OldestReducer r;
  const std::vector<LandmarkView> lms = {landmark(5, 1, 1, 3, 9), landmark(2, 1, 1, 3, 9),
                                         landmark(7, 1, 1, 1, 9)};
  EXPECT_EQ(ask(r, lms, {0, 1, 2}).id, 7);
  EXPECT_EQ(ask(r, lms, {0, 1}).id, 2);
  EXPECT_EQ(ask(r, lms, {0, 1}).score, 3.0);
}

TEST(InfoContentReducer, LowestInverseVarianceSum) {
  InfoContentReducer r;
  const std::vector<LandmarkView> lms = {landmark(1, 0.1, 0.1, 0, 0), landmark(2, 1.0, 0.05, 0, 0),
                                         landmark(3, 0.5, 0.5, 0, 0)};
  // I: 20, 21, 4.
  const auto c = ask(r, lms, {0, 1, 2});
  EXPECT_EQ(c.id, 3);
  EXPECT_DOUBLE_EQ(c.score, 4.0);
  EXPECT_EQ(ask(r, lms, {0, 1}).id, 1);
}

TEST(RandomReducer, DeterministicForASeedAndCoversCandidates) {
  std::vector<LandmarkView> lms;
  for (int i = 0; i < 10; ++i) lms.push_back(landmark(i, 1, 1, 0, 0));
  std::vector<std::size_t> all(10);
  std::iota(all.begin(), all.end(), 0);
  RandomReducer a(9), b(9), c(10);
  std::vector<LandmarkId> sa, sb, sc;
  std::set<LandmarkId> hit;
  for (int k = 0; k < 200; ++k) {
    sa.push_back(ask(a, lms, all).id);
    sb.push_back(ask(b, lms, all).id);
    sc.push_back(ask(c, lms, all).id);
    hit.insert(sa.back());
  }
  EXPECT_EQ(sa, sb);
  EXPECT_NE(sa, sc);
  EXPECT_EQ(hit.size(), 10u);
  EXPECT_EQ(ask(a, lms, {3}).id, 3);
}
