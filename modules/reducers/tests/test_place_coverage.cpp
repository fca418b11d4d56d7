#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <random>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/PlaceCoverageReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

PlaceCoverageOptions placeOptions(std::size_t k) {
  PlaceCoverageOptions o;
  o.min_landmarks = k;
  o.place_size = 1.0;  // place i: the cell [i, i + 1) x [0, 1)
  o.heading_sectors = 1;
  return o;
}

StepObservation at(StepIndex step, double x, std::vector<LandmarkId> seen) {
  StepObservation o;
  o.step = step;
  o.robot = Pose2(x, 0.5, 0);
  o.observed = std::move(seen);
  return o;
}

/// f(K) = sum over places of min(k, |K observed from the place|), by enumeration.
double coverageOf(const std::vector<std::vector<LandmarkId>>& places, const std::set<LandmarkId>& K,
                  std::size_t k) {
  double f = 0;
  for (const auto& p : places) {
    std::size_t n = 0;
    for (const LandmarkId id : p) n += K.count(id);
    f += static_cast<double>(std::min(n, k));
  }
  return f;
}

/// Hochdorfer & Schlegel Fig. 1 with the robot back in room 1. Room 1 (x in [0, 4), places 0-3):
/// landmarks 1-6, every one seen from every place of the room, and newcomer 10 seen at step 35.
/// Room 2 (x in [30, 32)): landmarks 7-9, seen as {7, 8} from place 30 and {8, 9} from place 31.
/// Cap 9: the newcomer makes 10, one must go.
FakeBackend roomsWithRobotInRoom1(BudgetManager& manager) {
  FakeBackend b({});
  for (LandmarkId id = 1; id <= 6; ++id) b.add(landmark(id, 0.05, 0.05, 0, 0));
  for (StepIndex s = 0; s < 8; ++s) {
    b.pose = Pose2(0.5 * static_cast<double>(s), 0.5, 0);
    for (LandmarkId id = 1; id <= 6; ++id) b.see(id, s);
    EXPECT_TRUE(manager.enforce(b, s).empty());
  }
  b.add(landmark(7, 0.5, 0.5, 20, 20));
  b.add(landmark(8, 0.5, 0.5, 20, 20));
  for (StepIndex s = 20; s < 24; ++s) {
    const bool first_half = s < 22;
    if (s == 22) b.add(landmark(9, 0.5, 0.5, 22, 22));
    b.pose = Pose2(first_half ? 30.5 : 31.5, 0.5, 0);
    for (const LandmarkId id :
         first_half ? std::vector<LandmarkId>{7, 8} : std::vector<LandmarkId>{8, 9})
      b.see(id, s);
    EXPECT_TRUE(manager.enforce(b, s).empty());
  }
  for (StepIndex s = 30; s < 35; ++s) {
    b.pose = Pose2(1.5, 0.5, 0);
    for (LandmarkId id = 1; id <= 6; ++id) b.see(id, s);
    EXPECT_TRUE(manager.enforce(b, s).empty());
  }
  b.add(landmark(10, 0.2, 0.2, 35, 35));
  for (LandmarkId id = 1; id <= 6; ++id) b.see(id, 35);
  // Information gains [bits]: room 1 well known but redundant, room 2 poorly known.
  b.gains = {{1, 6.0}, {2, 5.5}, {3, 5.0}, {4, 4.8}, {5, 4.6},
             {6, 1.0}, {7, 0.3}, {8, 0.8}, {9, 0.9}, {10, 0.1}};
  return b;
}

BudgetOptions budget(BudgetOptions::Protect protect) {
  BudgetOptions o;
  o.reducer = "place-coverage";
  o.max_landmarks = 9;
  o.protect_recent_steps = 5;
  o.protect = protect;
  return o;
}

}  // namespace

TEST(PlaceCoverageReducer, RobotInRoom1NewlyAddedDropsFromRoom1RecentlySeenCannot) {
  {
    auto reducer = std::make_unique<PlaceCoverageReducer>(placeOptions(2));
    PlaceCoverageReducer* pc = reducer.get();
    BudgetManager manager(budget(BudgetOptions::Protect::NewlyAdded), std::move(reducer));
    FakeBackend b = roomsWithRobotInRoom1(manager);
    const auto drops = manager.enforce(b, 35);
    ASSERT_EQ(drops.size(), 1u);
    // Room 1's places hold 7 > k landmarks: losing one costs no place; the least informative
    // of the room goes (the newcomer is protected while it converges).
    EXPECT_EQ(drops[0].id, 6);
    EXPECT_DOUBLE_EQ(drops[0].score, 0.0);
    EXPECT_EQ(drops[0].reason, "over_cap");
    // Every place keeps k = 2: 4 room-1 places + 2 room-2 places.
    EXPECT_DOUBLE_EQ(pc->coverage(), 12.0);
  }
  {
    // recently_seen: every room-1 landmark is in view, so protected; only room 2 can pay, and
    // a room-2 place loses coverage (documented in docs/ALGORITHMS.md).
    auto reducer = std::make_unique<PlaceCoverageReducer>(placeOptions(2));
    PlaceCoverageReducer* pc = reducer.get();
    BudgetManager manager(budget(BudgetOptions::Protect::RecentlySeen), std::move(reducer));
    FakeBackend b = roomsWithRobotInRoom1(manager);
    const auto drops = manager.enforce(b, 35);
    ASSERT_EQ(drops.size(), 1u);
    EXPECT_GE(drops[0].id, 7);
    EXPECT_LE(drops[0].id, 9);
    EXPECT_EQ(drops[0].id, 7);  // loss 1 like 9, lower gain; 8 would cost both places
    EXPECT_DOUBLE_EQ(drops[0].score, 1.0);
    EXPECT_DOUBLE_EQ(pc->coverage(), 11.0);
  }
}

TEST(PlaceCoverageReducer, GreedyDropEqualsExhaustiveBestSingleDrop) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 2 + rng() % 11;  // N <= 12 landmarks
    const std::size_t n_places = 1 + rng() % 8;
    const std::size_t k = 1 + rng() % 3;
    PlaceCoverageReducer reducer(placeOptions(k));
    std::vector<std::vector<LandmarkId>> places(n_places);
    for (std::size_t p = 0; p < n_places; ++p) {
      for (LandmarkId id = 1; id <= n; ++id)
        if (rng() % 3 == 0) places[p].push_back(id);
      // A place can be visited several times; the same sightings again change nothing.
      for (int visit = 0; visit < 2; ++visit)
        reducer.observe(at(10 * p + visit, static_cast<double>(p) + 0.5, places[p]));
    }
    ASSERT_EQ(reducer.placeCount(),
              std::count_if(places.begin(), places.end(), [](auto& p) { return !p.empty(); }));

    std::vector<LandmarkView> views;
    std::set<LandmarkId> K;
    FakeBackend backend({});
    for (LandmarkId id = 1; id <= n; ++id) {
      views.push_back(landmark(id, 0.1, 0.1, 0, 0));
      K.insert(id);
      backend.gains[id] = static_cast<double>(rng() % 4);  // many ties on purpose
    }
    // Drop one at a time down to one landmark, checking every greedy step.
    while (K.size() > 1) {
      const double f = coverageOf(places, K, k);
      ASSERT_DOUBLE_EQ(reducer.coverage(), f) << "trial " << trial;
      double best = -1;
      std::vector<std::size_t> candidates;
      for (std::size_t i = 0; i < views.size(); ++i) {
        candidates.push_back(i);
        std::set<LandmarkId> without = K;
        without.erase(views[i].id);
        const double fi = coverageOf(places, without, k);
        ASSERT_DOUBLE_EQ(reducer.loss(views[i].id), f - fi) << "trial " << trial;
        best = std::max(best, fi);
      }
      const DropContext ctx{backend, views, candidates, 100};
      const ReducerChoice c = reducer.choose(ctx);
      std::set<LandmarkId> without = K;
      without.erase(c.id);
      EXPECT_DOUBLE_EQ(coverageOf(places, without, k), best) << "trial " << trial;
      // Among the exhaustive best drops, the lowest information gain, then the lowest id.
      for (const auto& v : views) {
        std::set<LandmarkId> w = K;
        w.erase(v.id);
        if (coverageOf(places, w, k) == best && v.id != c.id) {
          const double gv = backend.gains[v.id], gc = backend.gains[c.id];
          EXPECT_TRUE(gc < gv || (gc == gv && c.id < v.id)) << "trial " << trial;
        }
      }
      reducer.forget(c.id);
      K.erase(c.id);
      views.erase(std::find_if(views.begin(), views.end(), [&](auto& v) { return v.id == c.id; }));
    }
  }
}

TEST(PlaceCoverageReducer, NearTiesGoToInformationGain) {
  PlaceCoverageOptions o = placeOptions(1);
  o.near_tie = 1.0;
  PlaceCoverageReducer reducer(o);
  reducer.observe(at(0, 0.5, {1, 2}));  // 2 > k: neither costs place 0
  reducer.observe(at(1, 1.5, {3}));     // 3 alone covers place 1: loss 1
  FakeBackend backend({});
  backend.gains = {{1, 5.0}, {2, 4.0}, {3, 0.5}};
  const std::vector<LandmarkView> views = {landmark(1, 1, 1, 0, 0), landmark(2, 1, 1, 0, 0),
                                           landmark(3, 1, 1, 1, 1)};
  const std::vector<std::size_t> all = {0, 1, 2};
  EXPECT_EQ(reducer.choose({backend, views, all, 2}).id, 3);  // loss 1 is within 1 of 0
  PlaceCoverageReducer strict(placeOptions(1));
  strict.observe(at(0, 0.5, {1, 2}));
  strict.observe(at(1, 1.5, {3}));
  EXPECT_EQ(strict.choose({backend, views, all, 2}).id, 2);
}

/// Landmark `id` at (x, 5) [m], first seen at `first`.
LandmarkView landmarkAt(LandmarkId id, double x, StepIndex first) {
  LandmarkView v = landmark(id, 0.1, 0.1, first, first);
  v.mean = Eigen::Vector2d(x, 5.0);
  return v;
}

/// The shipped admission on a scripted stream: cap 3, the robot stays in place 0 (k = 2), which
/// sees every landmark, so every coverage loss is 0 and the tie-break alone decides admission.
/// A newcomer has the lowest information gain after its one step of probation, as in the EKF.
TEST(PlaceCoverageReducer, SpreadTieBreakAdmitsANewcomerAwayFromTheKeptOnesRefusesACrowdedOne) {
  const auto scripted = [](PlaceCoverageOptions::TieBreak tie_break, std::vector<Eviction>* drops) {
    PlaceCoverageOptions o = placeOptions(2);
    o.tie_break = tie_break;
    BudgetOptions budget;
    budget.max_landmarks = 3;
    budget.protect_recent_steps = 5;
    budget.protect = BudgetOptions::Protect::NewlyAdded;
    budget.admission = BudgetOptions::Admission::Compete;
    BudgetManager manager(budget, std::make_unique<PlaceCoverageReducer>(o));
    // Kept: 1 and 2 half a metre apart, 3 ten metres away; all converged.
    FakeBackend b({landmarkAt(1, 0.0, 0), landmarkAt(2, 0.5, 0), landmarkAt(3, 10.0, 0)});
    b.gains = {{1, 6.0}, {2, 5.0}, {3, 7.0}, {4, 0.5}, {5, 0.5}};
    b.pose = Pose2(0.5, 0.5, 0);
    for (StepIndex s = 0; s < 10; ++s) {
      for (LandmarkId id = 1; id <= 3; ++id) b.see(id, s);
      EXPECT_TRUE(manager.enforce(b, s).empty());
    }
    // Step 10: newcomer 4, twenty metres from the others.
    b.add(landmarkAt(4, 30.0, 10));
    for (LandmarkId id = 1; id <= 4; ++id) b.see(id, 10);
    auto first = manager.enforce(b, 10);
    // Step 20: newcomer 5, 0.2 m from landmark 1 (if 1 is still there).
    b.add(landmarkAt(5, 0.2, 20));
    for (LandmarkId id = 1; id <= 5; ++id)
      if (b.has(id)) b.see(id, 20);
    auto second = manager.enforce(b, 20);
    EXPECT_EQ(b.landmarkCount(), 3u);
    drops->insert(drops->end(), first.begin(), first.end());
    drops->insert(drops->end(), second.begin(), second.end());
  };
  using T = PlaceCoverageOptions::TieBreak;
  std::vector<Eviction> ig, spread;
  scripted(T::InformationGain, &ig);
  // Information gain: every newcomer is the least informative after one step and is refused.
  ASSERT_EQ(ig.size(), 2u);
  EXPECT_EQ(ig[0].id, 4);
  EXPECT_EQ(ig[0].reason, "refused");
  EXPECT_EQ(ig[1].id, 5);
  EXPECT_EQ(ig[1].reason, "refused");

  scripted(T::Spread, &spread);
  ASSERT_EQ(spread.size(), 2u);
  // Newcomer 4 is far from everything: the most crowded kept landmark goes. 1 and 2 share the
  // least nearest-neighbour distance (0.5 m); 2 is nearer to its second neighbour (9.5 m < 10).
  EXPECT_EQ(spread[0].id, 2);
  EXPECT_EQ(spread[0].reason, "over_cap");
  EXPECT_DOUBLE_EQ(spread[0].score, 0.0);
  // Newcomer 5 lands 0.2 m from landmark 1: the pair ties at 0.2 m, 5's second neighbour (3,
  // 9.8 m) is nearer than 1's (10 m), so the newcomer is refused.
  EXPECT_EQ(spread[1].id, 5);
  EXPECT_EQ(spread[1].reason, "refused");
}

TEST(PlaceCoverageReducer, PlacesAreBoundedAndHeadingSectorsSplitACell) {
  PlaceCoverageOptions o = placeOptions(1);
  o.max_places = 2;
  PlaceCoverageReducer reducer(o);
  reducer.observe(at(0, 0.5, {1}));
  reducer.observe(at(1, 1.5, {2}));
  reducer.observe(at(2, 2.5, {3}));  // place 0, visited longest ago, is forgotten
  EXPECT_EQ(reducer.placeCount(), 2u);
  EXPECT_DOUBLE_EQ(reducer.loss(1), 0.0);
  EXPECT_DOUBLE_EQ(reducer.loss(2), 1.0);
  EXPECT_DOUBLE_EQ(reducer.coverage(), 2.0);

  // Defaults from the sensor: a quarter of the range, round(720 deg / fov) sectors.
  PlaceCoverageReducer from_sensor(PlaceCoverageOptions{});
  StepObservation s = at(0, 0.5, {1});
  s.sensor_max_range = 8;
  s.sensor_fov = M_PI;
  from_sensor.observe(s);
  EXPECT_DOUBLE_EQ(from_sensor.placeSize(), 2.0);
  EXPECT_EQ(from_sensor.headingSectors(), 4u);
  const auto facing = [](double yaw) { return Pose2(0.5, 0.5, yaw); };
  EXPECT_EQ(from_sensor.observedFrom(facing(0.1)), std::vector<LandmarkId>{1});
  EXPECT_TRUE(from_sensor.observedFrom(facing(M_PI)).empty());  // facing away: another place
}

TEST(PlaceCoverageReducer, RegisteredWithItsSectionAndValidatedKeys) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("PlaceCoverageReducer", "min_landmarks", "3");
  const auto r = builtinReducers().create("place-coverage", ini, 1);
  EXPECT_EQ(r->name(), "place-coverage");
  EXPECT_NE(observationKeeper(r.get()), nullptr);
  mrpt::config::CConfigFileMemory bad;
  bad.write("PlaceCoverageReducer", "min_landmarks", "0");
  EXPECT_THROW(builtinReducers().create("place-coverage", bad, 1), ConfigError);
  mrpt::config::CConfigFileMemory bad_tie;
  bad_tie.write("PlaceCoverageReducer", "tie_break", "nearest");
  try {
    builtinReducers().create("place-coverage", bad_tie, 1);
    FAIL() << "tie_break = nearest was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tie_break"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nearest"), std::string::npos) << e.what();
  }
}
