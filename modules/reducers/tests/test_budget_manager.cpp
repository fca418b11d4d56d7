#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <random>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {
BudgetOptions options(std::size_t cap, std::size_t protect) {
  BudgetOptions o;
  o.max_landmarks = cap;
  o.protect_recent_steps = protect;
  return o;
}
std::unique_ptr<Reducer> make(const std::string& name) {
  mrpt::config::CConfigFileMemory ini;
  return builtinReducers().create(name, ini, 42);
}
}  // namespace

TEST(BudgetManager, DropsUntilWithinCapNeverAProtectedOneWhileUnprotectedExist) {
  for (const std::string name : {"random", "oldest", "info-content"}) {
    FakeBackend backend({});
    BudgetOptions no_readmission = options(3, 5);
    no_readmission.readmit_evicted = false;  // so that evicted() records every drop
    BudgetManager manager(no_readmission, make(name));
    std::mt19937 rng(1);
    for (StepIndex step = 0; step < 60; ++step) {
      // Two new landmarks a step, seen now; older ones were last seen when added.
      backend.add(landmark(100 + 2 * step, 0.1 + 0.01 * (rng() % 50), 0.2, step, step));
      backend.add(landmark(101 + 2 * step, 0.3, 0.1 + 0.01 * (rng() % 50), step, step));
      auto present = backend.landmarks();
      const auto drops = manager.enforce(backend, step);
      EXPECT_LE(backend.landmarkCount(), 3u) << name;
      for (const auto& e : drops) {
        const auto isProtected = [&](const LandmarkView& l) { return step - l.last_step < 5; };
        const auto it =
            std::find_if(present.begin(), present.end(), [&](auto& l) { return l.id == e.id; });
        ASSERT_NE(it, present.end());
        // A protected landmark goes only when every landmark present is protected.
        const bool any_unprotected =
            std::any_of(present.begin(), present.end(), [&](auto& l) { return !isProtected(l); });
        EXPECT_EQ(isProtected(*it), !any_unprotected) << name << " step " << step;
        EXPECT_EQ(e.reason, any_unprotected ? "over_cap" : "over_cap_all_protected") << name;
        EXPECT_EQ(e.reducer, name);
        EXPECT_EQ(e.n_after + 1, e.n_before);
        present.erase(it);
      }
    }
    EXPECT_EQ(manager.evicted().size(), 117u) << name;
  }
}

TEST(BudgetManager, RemembersEvictedIdsOnlyWhenReadmissionIsOff) {
  FakeBackend backend({landmark(1, 0.5, 0.5, 0, 0), landmark(2, 0.1, 0.1, 0, 0)});
  BudgetManager manager(options(1, 0), make("oldest"));
  EXPECT_EQ(manager.enforce(backend, 3).size(), 1u);
  EXPECT_TRUE(manager.evicted().empty());  // memory must not grow with the drops
}

TEST(BudgetManager, ProtectedLandmarkGoesOnlyWhenAllAreProtected) {
  // Landmarks 1-3 seen at step 10 (protected with P = 5 at step 12), 4 seen at step 2.
  FakeBackend backend({landmark(1, 0.5, 0.5, 0, 10), landmark(2, 0.01, 0.01, 0, 10),
                       landmark(3, 0.9, 0.9, 0, 10), landmark(4, 0.001, 0.001, 0, 2)});
  BudgetManager manager(options(2, 5), make("info-content"));
  const auto drops = manager.enforce(backend, 12);
  ASSERT_EQ(drops.size(), 2u);
  // First the only unprotected one, though it is the most informative...
  EXPECT_EQ(drops[0].id, 4);
  EXPECT_EQ(drops[0].reason, "over_cap");
  // ...then the lowest-scored protected one (largest variance = lowest content).
  EXPECT_EQ(drops[1].id, 3);
  EXPECT_EQ(drops[1].reason, "over_cap_all_protected");
  EXPECT_NEAR(drops[1].score, 2 / 0.9, 1e-12);
}

TEST(BudgetManager, NoneNeverDropsAndShadowsAreLoggedWithAgreement) {
  FakeBackend backend(
      {landmark(1, 0.5, 0.5, 0, 0), landmark(2, 0.01, 0.01, 1, 1), landmark(3, 0.9, 0.9, 2, 2)});
  BudgetManager none(options(1, 0), make("none"));
  EXPECT_FALSE(none.reduces());
  EXPECT_TRUE(none.enforce(backend, 10).empty());
  EXPECT_EQ(backend.landmarkCount(), 3u);

  std::vector<std::unique_ptr<Reducer>> shadows;
  shadows.push_back(make("info-content"));
  shadows.push_back(make("oldest"));
  BudgetManager manager(options(1, 0), make("oldest"), std::move(shadows));
  const auto drops = manager.enforce(backend, 10);
  ASSERT_EQ(drops.size(), 2u);
  EXPECT_EQ(drops[0].id, 1);
  ASSERT_EQ(drops[0].shadow.size(), 2u);
  EXPECT_EQ(drops[0].shadow[0].first, "info-content");
  EXPECT_EQ(drops[0].shadow[0].second.id, 3);
  EXPECT_EQ(drops[0].shadow[1].second.id, 1);
  const auto agreements = manager.agreements();
  ASSERT_EQ(agreements.size(), 3u);  // oldest~info-content, oldest~oldest, info-content~oldest
  EXPECT_EQ(agreements[0].a, "oldest");
  EXPECT_EQ(agreements[0].b, "info-content");
  EXPECT_EQ(agreements[0].total, 2u);
  EXPECT_EQ(agreements[0].agree, 0u);  // oldest: 1 then 2; info-content: 3 then 3
  EXPECT_DOUBLE_EQ(agreements[1].rate(), 1.0);
}

TEST(BuiltinReducers, UnknownNameListsRegistered) {
  mrpt::config::CConfigFileMemory ini;
  try {
    builtinReducers().create("bogus", ini, 1);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("unknown reducer 'bogus' (registered: ", 0), 0u);
    EXPECT_NE(std::string(e.what()).find("info-content"), std::string::npos);
  }
}

namespace {
/// A shadow that fails at its second and third decisions, as mi does on a covariance that lost
/// positive definiteness; otherwise it picks the lowest id.
class FailingReducer : public Reducer {
 public:
  std::string name() const override { return "failing"; }
  ReducerChoice choose(const DropContext& ctx) override {
    ++calls;
    if (calls == 2 || calls == 3)
      throw std::runtime_error("covariance lost positive definiteness at call " +
                               std::to_string(calls) + "\nsecond line");
    LandmarkId best = ctx.landmarks[ctx.candidates[0]].id;
    for (const auto i : ctx.candidates) best = std::min(best, ctx.landmarks[i].id);
    return {best, 1.5};
  }
  int calls = 0;
};
}  // namespace

TEST(BudgetManager, AFailingShadowIsLoggedAndTheActiveDropsStand) {
  FakeBackend backend({});
  std::vector<std::unique_ptr<Reducer>> shadows;
  shadows.push_back(std::make_unique<FailingReducer>());
  shadows.push_back(make("oldest"));
  BudgetManager manager(options(2, 0), make("oldest"), std::move(shadows));
  std::vector<Eviction> all;
  for (StepIndex step = 0; step < 5; ++step) {
    backend.add(landmark(static_cast<LandmarkId>(10 + step), 1, 1, step, step));
    for (auto& e : manager.enforce(backend, step)) all.push_back(e);
    EXPECT_LE(backend.landmarkCount(), 2u);
  }
  // Steps 2, 3, 4 drop one landmark each, the oldest: the failing shadow changes nothing.
  ASSERT_EQ(all.size(), 3u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].id, static_cast<LandmarkId>(10 + i));
    ASSERT_EQ(all[i].shadow.size(), 2u);
    EXPECT_EQ(all[i].shadow[0].first, "failing");
    EXPECT_EQ(all[i].shadow[1].second.id, all[i].id);  // oldest agrees with itself
  }
  // Decision 1 answered; decisions 2 and 3 failed: no choice, NaN score, the error's first line.
  EXPECT_EQ(all[0].shadow[0].second.id, 10);
  EXPECT_TRUE(all[0].shadow_errors.empty());
  for (const std::size_t i : {1, 2}) {
    EXPECT_EQ(all[i].shadow[0].second.id, kNoLandmarkId);
    EXPECT_TRUE(std::isnan(all[i].shadow[0].second.score));
    ASSERT_EQ(all[i].shadow_errors.size(), 1u);
    EXPECT_EQ(all[i].shadow_errors[0].first, "failing");
    EXPECT_EQ(all[i].shadow_errors[0].second,
              "covariance lost positive definiteness at call " + std::to_string(i + 1));
  }
  const auto failures = manager.shadowFailures();
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].shadow, "failing");
  EXPECT_EQ(failures[0].failures, 2u);
  EXPECT_EQ(failures[0].first_step, 3u);
  EXPECT_EQ(failures[0].last_step, 4u);
  EXPECT_EQ(failures[0].first_error, "covariance lost positive definiteness at call 2");
  // Agreement counts only the decisions at which both answered.
  const auto agreements = manager.agreements();
  ASSERT_EQ(agreements.size(), 3u);  // oldest~failing, oldest~oldest, failing~oldest
  EXPECT_EQ(agreements[0].total, 1u);
  EXPECT_EQ(agreements[1].total, 3u);
  EXPECT_EQ(agreements[2].total, 1u);
}

TEST(BudgetManager, NoCapOnlyForReducersThatDecideTheMapSize) {
  BudgetOptions none = options(1, 0);
  none.max_landmarks.reset();
  try {
    BudgetManager manager(none, make("random"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "[LandmarkBudget] max_landmarks = none: reducer 'random' drops landmarks only to "
                 "keep the map under a cap, so it needs a number (no cap suits reducer none, and "
                 "mi in objective or incremental mode)");
  }
  EXPECT_THROW(BudgetManager(none, make("mi")), ConfigError);  // mi's default mode is cap
  BudgetManager reference(none, make("none"));
  EXPECT_FALSE(reference.capped());
  mrpt::config::CConfigFileMemory ini;
  for (const std::string mode : {"objective", "incremental"}) {
    ini.write("MutualInformationReducer", "mode", mode);
    BudgetManager mi(none, builtinReducers().create("mi", ini, 1));
    EXPECT_FALSE(mi.capped()) << mode;
    BudgetManager capped(options(4, 0), builtinReducers().create("mi", ini, 1));
    EXPECT_TRUE(capped.capped()) << mode;
  }
}
