#pragma once
// Shared by the backends' tests: two backends that must answer alike (a clone and its original).
#include <gtest/gtest.h>

#include <vector>

#include "budget_slam/core/Backend.h"

namespace budget_slam::testing {

inline std::vector<LandmarkId> idsOf(const Backend& b) {
  std::vector<LandmarkId> ids;
  for (const LandmarkView& v : b.landmarks()) ids.push_back(v.id);
  return ids;
}

/// Same trajectory, landmarks (means, covariances, sightings), pose and gains, bit for bit.
inline void expectSameBackend(const Backend& a, const Backend& b) {
  const auto ta = a.trajectory(), tb = b.trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t k = 0; k < ta.size(); ++k) {
    EXPECT_EQ(ta[k].step, tb[k].step);
    EXPECT_EQ(ta[k].pose.x, tb[k].pose.x);
    EXPECT_EQ(ta[k].pose.y, tb[k].pose.y);
    EXPECT_EQ(ta[k].pose.phi, tb[k].pose.phi);
  }
  const auto la = a.landmarks(), lb = b.landmarks();
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t k = 0; k < la.size(); ++k) {
    EXPECT_EQ(la[k].id, lb[k].id);
    EXPECT_EQ(la[k].mean, lb[k].mean);
    EXPECT_EQ(la[k].cov, lb[k].cov);
    EXPECT_EQ(la[k].n_obs, lb[k].n_obs);
    EXPECT_EQ(la[k].obs_mean, lb[k].obs_mean);
    EXPECT_EQ(la[k].last_step, lb[k].last_step);
  }
  EXPECT_EQ(a.robotPose().mean.vector(), b.robotPose().mean.vector());
  EXPECT_EQ(a.robotPose().cov, b.robotPose().cov);
  const auto ids = idsOf(a);
  EXPECT_EQ(a.informationGain(ids), b.informationGain(ids));
}

}  // namespace budget_slam::testing
