// The hindsight bound's selection (greedy insertion on the sum over places of log det) against
// exhaustive search, and the two instruments of the bounds, `hindsight` and `known-set`, on
// hand-made runs.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <Eigen/LU>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/RangeBearingModel.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/HindsightReducer.h"
#include "budget_slam/reducers/HindsightSelection.h"
#include "budget_slam/reducers/Instruments.h"
#include "budget_slam/reducers/KnownSetReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;
using budget_slam::testing::landmark;

namespace {

constexpr double kStdRange = 0.05, kStdBearing = 0.02;  // [m], [rad]
const double kGreedyRatio = 1 - std::exp(-1.0);

Eigen::Matrix3d prior() { return Eigen::Vector3d(0.04, 0.04, 0.4).asDiagonal(); }

/// The information of one noise-free reading of landmark `l` from `robot` (sensor at the origin).
Eigen::Matrix3d info(const Pose2& robot, const Eigen::Vector2d& l) {
  return readingInformation(predictRangeBearing(robot, {}, l).H_robot, kStdRange, kStdBearing);
}

/// `places` places along y = 0, each reading each of `n` landmarks (ids 1..n, in a 10 x 10 m
/// square) with probability `density`.
std::vector<PlaceReadings> randomPlaces(std::size_t n, std::size_t places, double density,
                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Vector2d> where;
  for (std::size_t i = 0; i < n; ++i) where.emplace_back(10 * u(rng), 1 + 9 * u(rng));
  std::vector<PlaceReadings> out(places);
  for (std::size_t p = 0; p < places; ++p) {
    const Pose2 robot(10.0 * p / places, 0, 2 * M_PI * u(rng));
    for (std::size_t i = 0; i < n; ++i)
      if (u(rng) < density) {
        out[p].ids.push_back(static_cast<LandmarkId>(i + 1));
        out[p].info.push_back(info(robot, where[i]));
      }
  }
  return out;
}

std::vector<LandmarkId> ids(std::size_t n) {
  std::vector<LandmarkId> out;
  for (std::size_t i = 1; i <= n; ++i) out.push_back(static_cast<LandmarkId>(i));
  return out;
}

}  // namespace

TEST(HindsightSelection, ObjectiveIsTheSumOverPlacesOfLogDet) {
  const auto places = randomPlaces(5, 4, 0.6, 3);
  double f = 0;
  for (const auto& p : places) {
    Eigen::Matrix3d lambda = prior();
    for (std::size_t j = 0; j < p.ids.size(); ++j)
      if (p.ids[j] == 2 || p.ids[j] == 5) lambda += p.info[j];
    f += std::log(lambda.determinant());
  }
  EXPECT_NEAR(logDetObjective(places, prior(), {5, 2}), f, 1e-9 * std::abs(f));
  EXPECT_NEAR(logDetObjective(places, prior(), {}), 4 * std::log(prior().determinant()), 1e-9);
}

TEST(HindsightSelection, GreedyEqualsExhaustiveWhereGreedyIsExact) {
  // Every landmark read from places of its own: F is modular and greedy is optimal; and k = 1,
  // where greedy is the exhaustive search itself.
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::size_t n = 8 + seed;  // up to 12
    const auto shared = randomPlaces(n, 10, 0.4, seed);
    std::vector<PlaceReadings> own;
    for (const auto& p : shared)
      for (std::size_t j = 0; j < p.ids.size(); ++j) own.push_back({{p.ids[j]}, {p.info[j]}});
    for (std::size_t k = 0; k <= n; ++k) {
      const auto g = greedyLogDetSelection(own, prior(), ids(n), k);
      const auto e = exhaustiveLogDetSelection(own, prior(), ids(n), k);
      EXPECT_EQ(g.selection.size(), std::min(k, n));
      EXPECT_NEAR(g.gain, e.gain, 1e-9 * std::max(1.0, e.gain)) << "seed " << seed << " k " << k;
    }
    const auto g = greedyLogDetSelection(shared, prior(), ids(n), 1);
    const auto e = exhaustiveLogDetSelection(shared, prior(), ids(n), 1);
    EXPECT_EQ(g.selection, e.selection) << seed;
  }
}

TEST(HindsightSelection, GreedyIsWithinOneMinusOneOverEOfExhaustiveEverywhereTested) {
  std::size_t cases = 0, exact = 0;
  double worst = 1;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const std::size_t n = 6 + seed % 7;  // 6 to 12 landmarks
    const auto places = randomPlaces(n, 12, 0.35 + 0.02 * (seed % 10), 100 + seed);
    for (std::size_t k = 1; k < n; ++k) {
      const auto g = greedyLogDetSelection(places, prior(), ids(n), k);
      const auto e = exhaustiveLogDetSelection(places, prior(), ids(n), k);
      ASSERT_EQ(g.selection.size(), k);
      EXPECT_LE(g.gain, e.gain * (1 + 1e-12)) << "seed " << seed << " k " << k;
      EXPECT_GE(g.gain, kGreedyRatio * e.gain) << "seed " << seed << " k " << k;
      worst = std::min(worst, e.gain > 0 ? g.gain / e.gain : 1.0);
      exact += g.selection == e.selection;
      ++cases;
    }
  }
  // Far above the guarantee in practice; most cases exact.
  EXPECT_GT(worst, 0.9);
  EXPECT_GT(exact, cases / 2);
  std::cout << "greedy/exhaustive: " << exact << " of " << cases << " exact, worst ratio " << worst
            << "\n";
}

TEST(HindsightSelection, CandidatesReadFromNoPlaceFillTheSetLast) {
  const auto places = randomPlaces(4, 6, 0.7, 9);
  const auto g = greedyLogDetSelection(places, prior(), {1, 2, 3, 4, 50, 60}, 5);
  EXPECT_EQ(g.selection, (std::vector<LandmarkId>{1, 2, 3, 4, 50}));
  EXPECT_THROW(exhaustiveLogDetSelection(places, prior(), ids(40), 20), std::length_error);
}

TEST(HindsightReducer, KeepCountsAsThePercentageCapsOfTheScripts) {
  EXPECT_EQ(HindsightOptions::keepCount("33.3333%", 15), 5u);
  EXPECT_EQ(HindsightOptions::keepCount("20%", 15), 3u);
  EXPECT_EQ(HindsightOptions::keepCount("20%", 2), 1u);
  EXPECT_EQ(HindsightOptions::keepCount("7", 100), 7u);
  for (const char* bad : {"0%", "101%", "x%", "%", "0", "-3", "4.5", ""}) {
    try {
      HindsightOptions::keepCount(bad, 10);
      FAIL() << bad;
    } catch (const KeyError& e) {
      EXPECT_EQ(e.section(), "HindsightReducer");
      EXPECT_EQ(e.key(), "keep");
    }
  }
}

TEST(HindsightReducer, KeepsTheGreedySelectionOfItsPlacesAfterTheLastStepOnly) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("HindsightReducer", "keep", "40%");
  ini.write("LocalizationInformationReducer", "place_size", "1");
  ini.write("LocalizationInformationReducer", "heading_sectors", "1");
  auto made = builtinReducers().create("hindsight", ini, 1);
  auto* h = dynamic_cast<HindsightReducer*>(made.get());
  ASSERT_NE(h, nullptr);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  std::map<LandmarkId, Eigen::Vector2d> where;
  std::vector<LandmarkView> map;
  for (LandmarkId id = 1; id <= 10; ++id) {
    where[id] = Eigen::Vector2d(20 * u(rng), 2 + 5 * u(rng));
    map.push_back(landmark(id, 1, 1, 0, 0));
  }
  FakeBackend b(map);
  for (StepIndex s = 0; s < 20; ++s) {
    StepObservation o;
    o.step = s;
    o.robot = Pose2(s, 0, 0);
    o.sensor_max_range = 8;
    for (const auto& [id, l] : where)
      if ((l - Eigen::Vector2d(s, 0)).norm() < 8) {
        const Eigen::Vector2d z = predictRangeBearing(o.robot, {}, l).z;
        o.observed.push_back(id);
        o.sightings.push_back({id, z(0), z(1)});
      }
    h->observe(o);
    EXPECT_TRUE(h->scheduled({b, s, false, {}}).drops.empty());
  }
  const auto plan = h->scheduled({b, 19, true, {}});
  const auto expected = greedyLogDetSelection(h->places(), h->prior(), ids(10), 4);
  EXPECT_EQ(h->selection().selection, expected.selection);
  ASSERT_EQ(plan.drops.size(), 6u);
  for (const auto& d : plan.drops)
    EXPECT_FALSE(std::count(expected.selection.begin(), expected.selection.end(), d.id)) << d.id;
  EXPECT_EQ(plan.reason, "hindsight");
}

TEST(HindsightReducer, AMissingPlacesRawlogIsTheKeyErrorNamingIt) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("HindsightReducer", "places_rawlogs", "/nonexistent/revisit.rawlog");
  try {
    builtinReducers().create("hindsight", ini, 1);
    FAIL() << "built without its places";
  } catch (const KeyError& e) {
    EXPECT_EQ(e.key(), "places_rawlogs");
    EXPECT_NE(std::string(e.what()).find("/nonexistent/revisit.rawlog"), std::string::npos);
  }
}

TEST(KnownSetReducer, DropsEverythingOutsideTheSetAtFirstSightOrAtTheEnd) {
  KnownSetOptions o;
  o.ids = {"2", "5", "9"};
  KnownSetReducer first(o);
  FakeBackend b({landmark(1, 1, 1, 0, 0), landmark(2, 1, 1, 0, 0), landmark(5, 1, 1, 0, 0),
                 landmark(7, 1, 1, 0, 0)});
  std::vector<LandmarkId> dropped;
  for (const auto& d : first.scheduled({b, 3, false, {}}).drops) dropped.push_back(d.id);
  EXPECT_EQ(dropped, (std::vector<LandmarkId>{1, 7}));
  // Over a cap: outside the set first, then the set's highest id.
  const auto lms = b.landmarks();
  EXPECT_EQ(first.choose({b, lms, {0, 1, 2, 3}, 3}).id, 1);
  EXPECT_EQ(first.choose({b, lms, {1, 2}, 3}).id, 5);
  o.when = KnownSetOptions::When::End;
  KnownSetReducer end(o);
  EXPECT_TRUE(end.scheduled({b, 3, false, {}}).drops.empty());
  EXPECT_EQ(end.scheduled({b, 3, true, {}}).drops.size(), 2u);
  o.ids = {};  // the empty set: every landmark goes
  EXPECT_EQ(KnownSetReducer(o).scheduled({b, 3, true, {}}).drops.size(), 4u);
  // Instruments, not rules: left out of compare's default list.
  EXPECT_TRUE(isInstrument("known-set"));
  EXPECT_TRUE(isInstrument("hindsight"));
  EXPECT_FALSE(isInstrument("localization-information"));
  for (const auto& n : instrumentNames()) EXPECT_NO_THROW(builtinReducers().entry(n)) << n;
  o.ids = {"3", "x"};
  try {
    KnownSetReducer bad(o);
    FAIL() << "a bad id passed";
  } catch (const KeyError& e) {
    EXPECT_EQ(std::string(e.what()),
              "[KnownSetReducer] ids = x: not a landmark id (an integer >= 0)");
  }
}
