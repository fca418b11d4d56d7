// Negative evidence: a kept landmark in range and in the field of view, seen before from where the
// robot stands, that is not observed pass after pass is distrusted and dropped first; out of the
// field of view, or behind what hid it from this place before, it is never counted as missed.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/NegativeEvidence.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

/// A 180-degree sensor reaching 3 m at the robot's centre.
SensorView halfCircle() {
  SensorView s;
  s.min_range = 0.2;
  s.max_range = 3;
  s.fov = M_PI;
  return s;
}

LandmarkView at(LandmarkId id, double x, double y, StepIndex last = 0) {
  LandmarkView l = landmark(id, 0.01, 0.01, 0, last);
  l.mean = Eigen::Vector2d(x, y);
  return l;
}

}  // namespace

TEST(NegativeEvidence, CountsOneMissAPassThroughViewAndASightingClearsThem) {
  NegativeEvidence ne({});  // K = 2, 2 unseen steps make a pass a miss, 0.5 m cells
  const std::vector<LandmarkView> map = {at(7, 2, 0)};
  const Pose2 facing(0.1, 0.1, 0), away(0.1, 0.1, M_PI);
  ne.update(0, facing, halfCircle(), map, {7});  // seen from this place: its view is clear
  EXPECT_EQ(ne.records().at(7).misses, 0u);
  StepIndex k = 1;
  // A pass of 5 steps in view without a sighting: one miss, counted at its second step.
  ne.update(k++, away, halfCircle(), map, {});  // the pass before ends (it was seen)
  ne.update(k++, facing, halfCircle(), map, {});
  EXPECT_EQ(ne.records().at(7).misses, 0u);
  for (int i = 0; i < 4; ++i) ne.update(k++, facing, halfCircle(), map, {});
  EXPECT_EQ(ne.records().at(7).misses, 1u);
  EXPECT_TRUE(ne.distrusted().empty());
  // Looking away ends the pass; the next pass is the second miss: distrusted.
  ne.update(k++, away, halfCircle(), map, {});
  ne.update(k++, facing, halfCircle(), map, {});
  ne.update(k++, facing, halfCircle(), map, {});
  EXPECT_EQ(ne.records().at(7).misses, 2u);
  EXPECT_EQ(ne.distrusted(), std::vector<LandmarkId>{7});
  EXPECT_EQ(ne.records().at(7).last_confirmed_step, 0);
  // Seen again: confirmed, trusted.
  ne.update(k, facing, halfCircle(), map, {7});
  EXPECT_EQ(ne.records().at(7).misses, 0u);
  EXPECT_EQ(ne.records().at(7).last_confirmed_step, k);
  EXPECT_TRUE(ne.distrusted().empty());
}

TEST(NegativeEvidence, OutOfViewOrFromAPlaceItWasNeverSeenFromIsNoMiss) {
  NegativeEvidence ne({});
  // Landmark 1 ahead at 2 m; landmark 2 behind the robot; landmark 3 beyond the range.
  const std::vector<LandmarkView> map = {at(1, 2, 0), at(2, -2, 0), at(3, 4.5, 0)};
  const Pose2 here(0.1, 0.1, 0);
  ne.update(0, here, halfCircle(), map, {1, 2, 3});  // all seen once from here (e.g. turning)
  for (StepIndex k = 1; k < 20; ++k) {
    // Turn away every fifth step so that passes end and new ones begin.
    const Pose2 pose = k % 5 == 0 ? Pose2(0.1, 0.1, M_PI / 2) : here;
    ne.update(k, pose, halfCircle(), map, {1});
  }
  EXPECT_EQ(ne.records().at(1).misses, 0u);
  EXPECT_EQ(ne.records().at(2).misses, 0u);  // out of the field of view
  EXPECT_EQ(ne.records().at(3).misses, 0u);  // out of range
  // From another place (2 m to the side, a wall between, say) landmark 1 is in range and in the
  // field of view but was never seen from there: not observed there is no evidence.
  const Pose2 beside(1.1, -1.6, M_PI / 2);
  ASSERT_TRUE(ne.inView(beside, halfCircle(), map[0].mean));
  for (StepIndex k = 20; k < 40; ++k)
    ne.update(k, k % 5 == 0 ? Pose2(1.1, -1.6, -M_PI / 2) : beside, halfCircle(), map, {});
  EXPECT_EQ(ne.records().at(1).misses, 0u);
  EXPECT_TRUE(ne.distrusted().empty());
  // Margins: a landmark just inside the range limit or the field of view's edge is not expected.
  EXPECT_FALSE(ne.inView(here, halfCircle(), Eigen::Vector2d(2.8, 0.1)));
  EXPECT_FALSE(ne.inView(here, halfCircle(), Eigen::Vector2d(0.1 + 0.02, 2.1)));
  EXPECT_TRUE(ne.inView(here, halfCircle(), Eigen::Vector2d(1.0, 1.5)));
}

TEST(NegativeEvidence, ARemovedLandmarkIsDroppedFirstOnceMissedInView) {
  // Four landmarks around the robot's place; landmark 3 leaves the world after step 0. The
  // reducer `info-content` would drop the least informative landmark (1, the widest covariance),
  // but over the cap the landmark missed in view goes first (over_cap), and under the cap too
  // (always). Off: the reducer's choice.
  for (const auto mode :
       {BudgetOptions::NegativeEvidenceMode::Off, BudgetOptions::NegativeEvidenceMode::OverCap,
        BudgetOptions::NegativeEvidenceMode::Always}) {
    BudgetOptions o;
    o.max_landmarks = 4;
    o.protect_recent_steps = 0;  // every landmark a candidate
    o.negative_evidence = mode;
    mrpt::config::CConfigFileMemory ini;
    BudgetManager manager(o, builtinReducers().create("info-content", ini, 1));
    LandmarkView vague = at(1, 2, 0.5);
    vague.cov *= 100;
    FakeBackend backend({vague, at(2, 2, -0.5), at(3, 2.5, 0), at(4, 1.5, 0)});
    backend.pose = Pose2(0.1, 0.1, 0);
    Step step;
    step.scan = RangeBearingScan();
    step.scan->min_range = 0.2;
    step.scan->max_range = 3;
    step.scan->fov_yaw = M_PI;
    std::vector<Eviction> drops;
    for (StepIndex k = 0; k < 12; ++k) {
      step.index = k;
      // Looking at the landmarks, away every fourth step (passes end); 3 is seen only at step 0.
      backend.pose.phi = k % 4 == 3 ? M_PI : 0;
      for (LandmarkId id : {1, 2, 3, 4})
        if ((id != 3 || k == 0) && backend.pose.phi == 0 && backend.has(id)) backend.see(id, k);
      if (k == 10) backend.add(at(5, 1, 1, 10));  // a newcomer: over the cap
      for (auto& e : manager.enforce(backend, step)) drops.push_back(e);
    }
    const std::string name = BudgetOptions::toString(mode);
    ASSERT_FALSE(drops.empty()) << name;
    if (mode == BudgetOptions::NegativeEvidenceMode::Off) {
      EXPECT_EQ(drops.size(), 1u);
      EXPECT_EQ(drops[0].id, 1) << name;
      EXPECT_EQ(drops[0].reason, "over_cap");
      EXPECT_EQ(manager.negativeEvidence(), nullptr);
      continue;
    }
    ASSERT_EQ(drops.size(), 1u) << name;
    EXPECT_EQ(drops[0].id, 3) << name;
    EXPECT_EQ(drops[0].reason, "negative_evidence") << name;
    EXPECT_EQ(drops[0].score, 2) << name;  // the misses that condemned it
    // Passes: steps 4-6 (a miss at 5), 8-10 (a miss at 9; step 0's pass saw it). always: dropped
    // at its second miss, under the cap; over_cap: when 5 came in over the cap.
    EXPECT_EQ(drops[0].step, mode == BudgetOptions::NegativeEvidenceMode::Always ? 9 : 10) << name;
    EXPECT_TRUE(backend.has(1) && backend.has(5)) << name;
    const auto* ne = manager.negativeEvidence();
    ASSERT_NE(ne, nullptr);
    EXPECT_EQ(ne->records().count(3), 0u);  // forgotten with the landmark
    EXPECT_EQ(ne->records().at(1).last_confirmed_step, 10);
  }
}

TEST(NegativeEvidence, OptionsAreCheckedWhereRead) {
  const auto errorOf = [](const std::string& key, const std::string& value) {
    mrpt::config::CConfigFileMemory ini;
    ini.write("LandmarkBudget", key, value);
    BudgetOptions o;
    try {
      o.loadFromConfigFile(ini, "LandmarkBudget");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(errorOf("negative_evidence", "on"),
            "[LandmarkBudget] negative_evidence = 'on': must be one of off, over_cap, always");
  EXPECT_EQ(errorOf("misses_to_distrust", "0"),
            "[LandmarkBudget] misses_to_distrust = 0: must be at least 1");
  EXPECT_EQ(errorOf("miss_min_view_steps", "0"),
            "[LandmarkBudget] miss_min_view_steps = 0: must be at least 1");
  EXPECT_NE(errorOf("viewpoint_cell", "0").find("viewpoint_cell = 0"), std::string::npos);
  EXPECT_NE(errorOf("view_margin_deg", "-1").find("view_margin_deg"), std::string::npos);
  EXPECT_EQ(errorOf("negative_evidence", "always"), "");
  mrpt::config::CConfigFileMemory ini;
  ini.write("LandmarkBudget", "negative_evidence", "over_cap");
  ini.write("LandmarkBudget", "misses_to_distrust", "3");
  BudgetOptions o;
  o.loadFromConfigFile(ini, "LandmarkBudget");
  EXPECT_EQ(o.negative_evidence, BudgetOptions::NegativeEvidenceMode::OverCap);
  EXPECT_EQ(o.misses_to_distrust, 3u);
}
