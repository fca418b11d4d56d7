#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/RefusalMemory.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

std::unique_ptr<Reducer> make(const std::string& name) {
  mrpt::config::CConfigFileMemory ini;
  return builtinReducers().create(name, ini, 42);
}

BudgetOptions competing(std::size_t cap) {
  BudgetOptions o;
  o.max_landmarks = cap;
  o.protect_recent_steps = 5;
  o.protect = BudgetOptions::Protect::NewlyAdded;
  o.admission = BudgetOptions::Admission::Compete;
  o.retry_after_steps = 10;
  return o;
}

/// A step whose scan reads landmarks `ids`.
Step scanOf(StepIndex index, const std::vector<LandmarkId>& ids) {
  Step s;
  s.index = index;
  s.scan = RangeBearingScan{};
  for (const LandmarkId id : ids) s.scan->readings.push_back({id, 3.0, 0.1, 0});
  return s;
}

/// Variance [m^2] of each scripted landmark: info-content keeps the smallest.
double varianceOf(LandmarkId id) { return id == 4 ? 2.0 : id == 5 ? 0.01 : 0.1 * double(id); }

/// Plays `steps` steps of a scripted stream through the manager: what the admissible step still
/// reads enters the fake map (new ids as newcomers of that step) or is seen again.
std::vector<Eviction> play(BudgetManager& manager, FakeBackend& b, StepIndex from, StepIndex to,
                           const std::vector<LandmarkId>& in_view, std::size_t cap) {
  std::vector<Eviction> all;
  for (StepIndex s = from; s < to; ++s) {
    const Step filtered = manager.admissible(scanOf(s, in_view));
    for (const auto& r : filtered.scan->readings) {
      if (!b.has(r.id)) b.add(landmark(r.id, varianceOf(r.id), varianceOf(r.id), s, s));
      b.see(r.id, s);
    }
    const auto drops = manager.enforce(b, s);
    EXPECT_LE(b.landmarkCount(), cap) << "step " << s;
    all.insert(all.end(), drops.begin(), drops.end());
  }
  return all;
}

}  // namespace

TEST(Admission, WeakNewcomerRefusedStrongOneReplacesTheWeakestAndRefusalsWait) {
  FakeBackend b({});
  BudgetManager manager(competing(3), make("info-content"));
  // Landmarks 1-3 (variances 0.1, 0.2, 0.3) fill the map and converge.
  EXPECT_TRUE(play(manager, b, 0, 10, {1, 2, 3}, 3).empty());

  // Newcomer 4 (variance 2: weaker than every kept landmark) stays in view from step 10 to 59.
  const auto drops = play(manager, b, 10, 60, {1, 2, 3, 4}, 3);
  // Refused at 10, withheld for 10 steps, refused at 21, withheld 20, refused at 42 (then 40).
  ASSERT_EQ(drops.size(), 3u);
  const StepIndex expected[] = {10, 21, 42};
  for (std::size_t i = 0; i < drops.size(); ++i) {
    EXPECT_EQ(drops[i].id, 4);
    EXPECT_EQ(drops[i].reason, "refused");
    EXPECT_EQ(drops[i].step, expected[i]);
  }
  EXPECT_EQ(manager.refusals().refusals(4), 3u);
  EXPECT_EQ(manager.refusals().retryAt(4), 42u + 1 + 40);
  // While withheld, the step's readings of 4 are left out; the others stay.
  const Step filtered = manager.admissible(scanOf(60, {1, 4, 2}));
  ASSERT_EQ(filtered.scan->readings.size(), 2u);
  EXPECT_EQ(filtered.scan->readings[0].id, 1);
  EXPECT_EQ(filtered.scan->readings[1].id, 2);
  EXPECT_FALSE(b.has(4));

  // Newcomer 5 (variance 0.01: stronger than all) replaces the weakest kept landmark, 3.
  const auto replace = play(manager, b, 60, 61, {1, 2, 3, 5}, 3);
  ASSERT_EQ(replace.size(), 1u);
  EXPECT_EQ(replace[0].id, 3);
  EXPECT_EQ(replace[0].reason, "over_cap");
  EXPECT_TRUE(b.has(5));
  EXPECT_EQ(manager.refusals().refusals(5), 0u);
}

TEST(Admission, AlwaysLetsTheWeakNewcomerInAndDropsAKeptLandmark) {
  FakeBackend b({});
  BudgetOptions o = competing(3);
  o.admission = BudgetOptions::Admission::Always;
  BudgetManager manager(o, make("info-content"));
  play(manager, b, 0, 10, {1, 2, 3}, 3);
  const auto drops = play(manager, b, 10, 11, {1, 2, 3, 4}, 3);
  ASSERT_EQ(drops.size(), 1u);
  // Newly added 4 is protected while it converges: a kept landmark pays.
  EXPECT_EQ(drops[0].id, 3);
  EXPECT_TRUE(b.has(4));
  EXPECT_EQ(manager.refusals().size(), 0u);
}

TEST(Admission, ReadmissionStillWorksWithCompete) {
  // A landmark dropped over the cap (not refused) seen again comes back as a newcomer and
  // competes for its place; with readmit_evicted = false its readings are left out for good.
  for (const bool readmit : {true, false}) {
    FakeBackend b({});
    BudgetOptions o = competing(2);
    o.readmit_evicted = readmit;
    BudgetManager manager(o, make("info-content"));
    play(manager, b, 0, 10, {1, 3}, 2);
    // Newcomer 2 (variance 0.2) beats kept 3 (0.3): 3 is dropped over the cap.
    const auto first = play(manager, b, 10, 11, {1, 2}, 2);
    ASSERT_EQ(first.size(), 1u) << readmit;
    EXPECT_EQ(first[0].id, 3);
    EXPECT_EQ(first[0].reason, "over_cap");
    play(manager, b, 11, 20, {1, 2}, 2);
    const Step seen_again = manager.admissible(scanOf(20, {1, 3}));
    EXPECT_EQ(seen_again.scan->readings.size(), readmit ? 2u : 1u);
    const auto back = play(manager, b, 20, 21, {1, 3}, 2);
    if (readmit) {
      // It re-entered and competed: still the weakest, so refused this time.
      ASSERT_EQ(back.size(), 1u);
      EXPECT_EQ(back[0].id, 3);
      EXPECT_EQ(back[0].reason, "refused");
    } else {
      EXPECT_TRUE(back.empty());
      EXPECT_EQ(manager.evicted().count(3), 1u);
    }
    EXPECT_FALSE(b.has(3));
  }
}

TEST(RefusalMemory, BoundedOldestForgottenFirstAndWaitDoubles) {
  RefusalMemory m(2, 5);
  m.refused(7, 0);
  EXPECT_TRUE(m.withheld(7, 5));
  EXPECT_FALSE(m.withheld(7, 6));
  m.refused(7, 6);
  EXPECT_EQ(m.retryAt(7), 6u + 1 + 10);
  m.refused(8, 7);
  m.refused(9, 8);  // capacity 2: 7, refused longest ago, is forgotten
  EXPECT_EQ(m.size(), 2u);
  EXPECT_EQ(m.refusals(7), 0u);
  EXPECT_FALSE(m.withheld(7, 8));
  m.admitted(8);
  EXPECT_EQ(m.size(), 1u);
  for (int i = 0; i < 20; ++i) m.refused(9, 100);
  EXPECT_EQ(m.retryAt(9), 100u + 1 + 5 * 64);  // at most 64 base waits
  EXPECT_THROW(RefusalMemory(0, 1), std::invalid_argument);
}

TEST(BudgetOptions, ProtectAndAdmissionKeysAreValidatedWhereRead) {
  BudgetOptions o;
  mrpt::config::CConfigFileMemory ini;
  ini.write("LandmarkBudget", "protect", "newly_added");
  ini.write("LandmarkBudget", "admission", "compete");
  ini.write("LandmarkBudget", "retry_after_steps", "4");
  o.loadFromConfigFile(ini, "LandmarkBudget");
  EXPECT_EQ(o.protect, BudgetOptions::Protect::NewlyAdded);
  EXPECT_EQ(o.admission, BudgetOptions::Admission::Compete);
  EXPECT_EQ(o.retry_after_steps, 4u);
  mrpt::config::CConfigFileMemory bad;
  bad.write("LandmarkBudget", "admission", "sometimes");
  try {
    BudgetOptions().loadFromConfigFile(bad, "LandmarkBudget");
    FAIL();
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("LandmarkBudget"), std::string::npos) << what;
    EXPECT_NE(what.find("admission"), std::string::npos) << what;
    EXPECT_NE(what.find("sometimes"), std::string::npos) << what;
  }
}
