#include <gtest/gtest.h>

#include <cmath>

#include "budget_slam/metrics/RelativePoseError.h"

using namespace budget_slam::metrics;
using budget_slam::Pose2;

namespace {
/// 41 poses along +x (or along `yaw`), 1 m apart: 31 stretches of 10 m (i = 0..30, j = i + 10);
/// poses 31.. start none.
std::vector<Pose2> straight(double yaw = 0) {
  std::vector<Pose2> p;
  for (int k = 0; k <= 40; ++k) p.push_back({k * std::cos(yaw), k * std::sin(yaw), yaw});
  return p;
}
}  // namespace

TEST(RelativePoseError, ScaleDriftOfOnePercentIsTenCentimetresPerTenMetres) {
  const auto truth = straight();
  auto est = truth;
  for (auto& p : est) p.x *= 1.01;
  const auto e = relativePoseError(est, truth);
  EXPECT_EQ(e.pairs, 31u);
  EXPECT_NEAR(e.rmse, 0.1, 1e-12);
  EXPECT_NEAR(e.max, 0.1, 1e-12);
}

TEST(RelativePoseError, BlindToARigidTransformOfTheWholeEstimate) {
  const auto truth = straight(0.3);
  std::vector<Pose2> est;
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (const auto& p : truth)
    est.push_back({5 + c * p.x - s * p.y, -2 + s * p.x + c * p.y, p.phi + 0.7});
  const auto e = relativePoseError(est, truth);
  EXPECT_EQ(e.pairs, 31u);
  EXPECT_NEAR(e.rmse, 0, 1e-12);
}

TEST(RelativePoseError, AJumpCountsOnlyInThePairThatSpansIt) {
  // The truth heads north; the estimate jumps 0.5 m east between 25 and 26 m. In the frame of a
  // pose heading north that is 0.5 m to the right: the 10 pairs that span it (i = 16..25) have it.
  const auto truth = straight(M_PI / 2);
  auto est = truth;
  for (int k = 26; k <= 40; ++k) est[k].x += 0.5;
  const auto e = relativePoseError(est, truth);
  EXPECT_EQ(e.pairs, 31u);
  EXPECT_NEAR(e.rmse, std::sqrt(10 * 0.25 / 31), 1e-12);
  EXPECT_NEAR(e.max, 0.5, 1e-12);
}

TEST(RelativePoseError, HeadingErrorAtThePairStartTurnsTheStretch) {
  // The estimate turned by 2 degrees about the start: a rigid rotation when the headings turn
  // too; with the headings right, each 10 m stretch ends 2·10·sin(1 deg) m off.
  const auto truth = straight();
  std::vector<Pose2> est;
  const double a = 2 * M_PI / 180;
  for (const auto& p : truth) est.push_back({p.x * std::cos(a), p.x * std::sin(a), a});
  // The stretches of the estimate are the truth's turned by a, seen from a pose turned by a: no
  // error at all (a rigid rotation), unlike a heading error that only the poses carry:
  EXPECT_NEAR(relativePoseError(est, truth).rmse, 0, 1e-12);
  for (auto& p : est) p.phi = 0;  // positions turned, headings right
  EXPECT_NEAR(relativePoseError(est, truth).rmse, 2 * 10 * std::sin(a / 2), 1e-12);
}

TEST(RelativePoseError, StillStepsPairWithTheEarliestPoseAndShortPathsWithNone) {
  // Standing still for poses 11..14 at 10 m: pose 0's stretch ends at 10, not at a later still
  // pose (whose estimate has drifted on); pose 1 never gets 10 m away.
  std::vector<Pose2> truth;
  for (int k = 0; k <= 10; ++k) truth.push_back({double(k), 0, 0});
  for (int k = 0; k < 4; ++k) truth.push_back({10, 0, 0});
  auto est = truth;
  for (std::size_t k = 11; k < est.size(); ++k) est[k].y = 1;  // drift while still
  const auto still = relativePoseError(est, truth);
  EXPECT_EQ(still.pairs, 1u);
  EXPECT_NEAR(still.rmse, 0, 1e-12);

  truth = straight();
  truth.resize(10);  // 9 m
  const auto e = relativePoseError(truth, truth);
  EXPECT_EQ(e.pairs, 0u);
  EXPECT_TRUE(std::isnan(e.rmse));
}
