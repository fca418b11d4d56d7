// LandmarkTracks: the sightings both backends keep per landmark (Hochdorfer & Schlegel Eq. 1-2).
#include <gtest/gtest.h>

#include "budget_slam/core/LandmarkTracks.h"

using namespace budget_slam;

TEST(LandmarkTracks, RunningMeanFirstAndLastStep) {
  LandmarkTracks t;
  t.addSighting(7, Eigen::Vector2d(1, 2), 4);
  t.addSighting(7, Eigen::Vector2d(3, -2), 9);
  t.addSighting(7, Eigen::Vector2d(2, 3), 11);
  t.addSighting(2, Eigen::Vector2d(5, 5), 11);
  const LandmarkTrack& a = t.at(7);
  EXPECT_EQ(a.n, 3u);
  EXPECT_TRUE(a.obs_mean.isApprox(Eigen::Vector2d(2, 1), 1e-15));  // mean of the three positions
  EXPECT_EQ(a.first_step, 4u);
  EXPECT_EQ(a.last_step, 11u);
  EXPECT_EQ(t.observedAt(11), (std::vector<LandmarkId>{2, 7}));  // sorted by id
  EXPECT_TRUE(t.observedAt(9).empty());                          // 7 was seen again since

  LandmarkView v;
  a.describe(&v);
  EXPECT_EQ(v.n_obs, 3u);
  EXPECT_EQ(v.obs_mean, a.obs_mean);
  EXPECT_EQ(v.first_step, 4u);
  EXPECT_EQ(v.last_step, 11u);

  // A removed landmark seen again starts a new track.
  t.erase(7);
  EXPECT_EQ(t.find(7), nullptr);
  t.addSighting(7, Eigen::Vector2d(0, 0), 20);
  EXPECT_EQ(t.at(7).n, 1u);
  EXPECT_EQ(t.at(7).first_step, 20u);
  EXPECT_THROW(t.at(99), std::out_of_range);
}
