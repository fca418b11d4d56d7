#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "FakeBackend.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/RangeBearingModel.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/LocalizationInformationReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::FakeBackend;

namespace {

constexpr double kStdRange = 0.05, kStdBearing = 0.02;  // [m], [rad]
using Objective = LocalizationInformationOptions::Objective;

LocalizationInformationOptions options(Objective objective = Objective::SumLogDet) {
  LocalizationInformationOptions o;
  o.objective = objective;
  o.place_size = 1.0;  // place i: the cell [i, i + 1) x [0, 1)
  o.heading_sectors = 1;
  o.prior_std_xy = 5.0;
  o.prior_std_yaw_deg = 90;
  return o;
}

/// A step at robot pose `robot` reading the landmarks `ids` at `where` without noise.
StepObservation readings(StepIndex step, const Pose2& robot, const Pose2& sensor,
                         const std::vector<LandmarkId>& ids,
                         const std::map<LandmarkId, Eigen::Vector2d>& where) {
  StepObservation o;
  o.step = step;
  o.robot = robot;
  o.sensor_pose = sensor;
  o.observed = ids;
  for (const LandmarkId id : ids) {
    const Eigen::Vector2d z = predictRangeBearing(robot, sensor, where.at(id)).z;
    o.sightings.push_back({id, z(0), z(1)});
  }
  return o;
}

/// The pose information of one reading by central differences of the reading model [1/m^2...].
Eigen::Matrix3d numericalInformation(const Pose2& robot, const Pose2& sensor,
                                     const Eigen::Vector2d& l) {
  Eigen::Matrix<double, 2, 3> J;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Pose2 p = robot, m = robot;
    (k == 0 ? p.x : k == 1 ? p.y : p.phi) += h;
    (k == 0 ? m.x : k == 1 ? m.y : m.phi) -= h;
    Eigen::Vector2d d = predictRangeBearing(p, sensor, l).z - predictRangeBearing(m, sensor, l).z;
    d(1) = std::remainder(d(1), 2 * M_PI);
    J.col(k) = d / (2 * h);
  }
  const Eigen::Matrix2d Rinv =
      Eigen::Vector2d(1 / (kStdRange * kStdRange), 1 / (kStdBearing * kStdBearing)).asDiagonal();
  return J.transpose() * Rinv * J;
}

/// A random world for the brute-force comparisons: `n` landmarks in a 10 x 10 m square, 8 places
/// (robot poses along y = 0.5) each reading a random subset of them.
struct RandomCase {
  std::map<LandmarkId, Eigen::Vector2d> where;
  std::vector<std::pair<Pose2, std::vector<LandmarkId>>> places;
};

RandomCase randomCase(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  RandomCase c;
  for (std::size_t i = 0; i < n; ++i)
    c.where[static_cast<LandmarkId>(i + 1)] = Eigen::Vector2d(10 * u(rng), 1 + 9 * u(rng));
  for (int p = 0; p < 8; ++p) {
    const Pose2 robot(p + 0.5, 0.5, 2 * M_PI * u(rng));
    std::vector<LandmarkId> ids;
    for (const auto& [id, _] : c.where)
      if (u(rng) < 0.45) ids.push_back(id);
    if (ids.empty()) ids.push_back(static_cast<LandmarkId>(1 + p % n));
    c.places.push_back({robot, ids});
  }
  return c;
}

/// The objectives of the kept set `K` from scratch: (sum, min) over places of log det.
std::pair<double, double> objectivesOf(const RandomCase& c, const std::set<LandmarkId>& K,
                                       const Eigen::Matrix3d& prior) {
  double sum = 0, least = std::numeric_limits<double>::infinity();
  for (const auto& [robot, ids] : c.places) {
    Eigen::Matrix3d lambda = prior;
    for (const LandmarkId id : ids)
      if (K.count(id)) lambda += numericalInformation(robot, {}, c.where.at(id));
    const double ld = std::log(lambda.determinant());
    sum += ld;
    least = std::min(least, ld);
  }
  return {sum, least};
}

std::vector<LandmarkView> views(const std::set<LandmarkId>& K) {
  std::vector<LandmarkView> out;
  for (const LandmarkId id : K) out.push_back(budget_slam::testing::landmark(id, 1, 1, 0, 0));
  return out;
}

}  // namespace

TEST(LocalizationInformationReducer, PlaceInformationEqualsNumericalJacobians) {
  // A sensor 0.3 m ahead of the robot's centre, turned 0.1 rad; three landmarks read from one
  // place: Lambda_p = Lambda_0 + sum of J^T R^-1 J with J by central differences.
  LocalizationInformationReducer r(options(), kStdRange, kStdBearing);
  const Pose2 robot(0.4, 0.6, 0.7), sensor(0.3, 0.05, 0.1);
  const std::map<LandmarkId, Eigen::Vector2d> where = {{1, {3, 2}}, {2, {-1, 4}}, {3, {2.5, -2}}};
  r.observe(readings(0, robot, sensor, {1, 2, 3}, where));
  Eigen::Matrix3d expected = r.prior();
  for (const auto& [id, l] : where) expected += numericalInformation(robot, sensor, l);
  const Eigen::Matrix3d got = r.placeInformation(robot);
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff())
      << "got\n"
      << got << "\nexpected\n"
      << expected;
  // The prior: sigma 5 m in x and y, 90 deg in yaw.
  EXPECT_NEAR(r.prior()(0, 0), 1 / 25.0, 1e-15);
  EXPECT_NEAR(r.prior()(2, 2), 1 / std::pow(M_PI / 2, 2), 1e-12);
  // A second reading of landmark 1 from the same place counts once: the place holds the mean
  // information of its readings of each landmark.
  r.observe(readings(1, robot, sensor, {1}, where));
  EXPECT_LT((r.placeInformation(robot) - expected).cwiseAbs().maxCoeff(),
            1e-6 * expected.cwiseAbs().maxCoeff());
}

TEST(LocalizationInformationReducer, DropsAreExactGreedyStepsEqualToBruteForce) {
  // What is compared, for N = 5..12 landmarks, two seeds each, both objectives, at every drop of
  // a removal sequence from N landmarks down to one:
  //  (1) every landmark's loss kept lazily by the reducer equals F(K) - F(K \ {l}) computed from
  //      scratch (numerical Jacobians, every place's determinant), and so does minLoss for the
  //      least place (a loss below 1e-9 of the least place's log det is round-off, read as 0);
  //  (2) the reducer's choice equals the exhaustive argmin of those losses (ties: the sum's
  //      loss, then the lowest id), i.e. lazy greedy = plain greedy by exhaustive evaluation;
  //  (3) the set the greedy removal reaches at each size m, against the exhaustive optimum of F
  //      over all subsets of size m: measured (worst case printed, 0.85 when written, at m = 1),
  //      and at least 80% of the optimum's gain over the prior on every case here (removal
  //      greedy has no general (1 - 1/e) guarantee, so this is a measurement, not a bound).
  double worst_ratio = 1;
  for (const Objective objective : {Objective::SumLogDet, Objective::MinLogDet})
    for (std::size_t n = 5; n <= 12; ++n)
      for (std::uint64_t seed : {n, n + 100}) {
        const RandomCase c = randomCase(n, seed);
        LocalizationInformationReducer r(options(objective), kStdRange, kStdBearing);
        StepIndex step = 0;
        for (const auto& [robot, ids] : c.places)
          r.observe(readings(step++, robot, {}, ids, c.where));
        std::set<LandmarkId> K;
        for (const auto& [id, _] : c.where) K.insert(id);
        const double base = objectivesOf(c, {}, r.prior()).first;
        while (K.size() > 1) {
          const auto [f, least] = objectivesOf(c, K, r.prior());
          EXPECT_NEAR(r.objective(), f, 1e-6 * std::abs(f) + 1e-6);
          std::tuple<double, double, LandmarkId> best{1e300, 1e300, 0};
          for (const LandmarkId id : K) {
            std::set<LandmarkId> without = K;
            without.erase(id);
            const auto [f2, least2] = objectivesOf(c, without, r.prior());
            EXPECT_NEAR(r.loss(id), f - f2, 1e-6 * std::abs(f) + 1e-7) << "landmark " << id;
            EXPECT_NEAR(r.minLoss(id), least - least2, 1e-6 * std::abs(least) + 1e-7);
            const double min_loss =
                least - least2 > 1e-9 * std::max(1.0, std::abs(least)) ? least - least2 : 0.0;
            const double key = objective == Objective::SumLogDet ? f - f2 : min_loss;
            // equal up to round-off counts as a tie
            const auto rounded = [](double v) { return std::round(v * 1e6) / 1e6; };
            best = std::min(best, {rounded(key), rounded(f - f2), id});
          }
          std::vector<std::size_t> all(K.size());
          for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
          const auto lms = views(K);
          FakeBackend backend(lms);
          const ReducerChoice choice = r.choose({backend, lms, all, step});
          EXPECT_EQ(choice.id, std::get<2>(best)) << "N = " << n << ", |K| = " << K.size();
          K.erase(choice.id);
          r.forget(choice.id);
          if (objective == Objective::SumLogDet) {
            // (3) the exhaustive optimum over the subsets of this size
            std::vector<LandmarkId> ids;
            for (const auto& [id, _] : c.where) ids.push_back(id);
            double opt = -1e300;
            for (unsigned mask = 0; mask < (1u << n); ++mask) {
              if (static_cast<std::size_t>(__builtin_popcount(mask)) != K.size()) continue;
              std::set<LandmarkId> S;
              for (std::size_t i = 0; i < n; ++i)
                if (mask & (1u << i)) S.insert(ids[i]);
              opt = std::max(opt, objectivesOf(c, S, r.prior()).first);
            }
            const double ratio = (objectivesOf(c, K, r.prior()).first - base) / (opt - base);
            worst_ratio = std::min(worst_ratio, ratio);
            EXPECT_GE(ratio, 0.8) << "N = " << n << ", |K| = " << K.size();
          }
        }
      }
  std::cout << "removal greedy / exhaustive optimum, gain over the prior, worst case: "
            << worst_ratio << "\n";
}

TEST(LocalizationInformationReducer, GeometryNotCountsTwoLandmarksInLineWithTheRobot) {
  // Range-bearing readings of two distinct landmarks always fix a 2D pose, so the exact
  // degeneracies are one landmark (or two at one point): rank 2, the robot's rotation about the
  // landmark unobserved. Two landmarks in line with the robot are the near-degenerate case: the
  // only thing across the line is their bearing difference, so the least eigenvalue of their
  // information vanishes as their ranges approach each other, where two landmarks at right
  // angles give a well-conditioned place. A count of landmarks sees no difference.
  const auto info = [](std::vector<Eigen::Vector2d> ls) {
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    for (const auto& l : ls)
      I += readingInformation(predictRangeBearing({0, 0, 0}, {0, 0, 0}, l).H_robot, kStdRange,
                              kStdBearing);
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  };
  const auto one = info({{3, 0}});
  EXPECT_LT(std::abs(one(0)), 1e-9 * one(2));  // rank 2
  const auto same_point = info({{3, 0}, {3, 0}});
  EXPECT_LT(std::abs(same_point(0)), 1e-9 * same_point(2));  // rank 2
  const auto in_line = info({{3, 0}, {3.1, 0}});
  const auto in_line_closer = info({{3, 0}, {3.01, 0}});
  const auto right_angle = info({{3, 0}, {0, 3.1}});
  EXPECT_LT(in_line(0), 1e-3 * right_angle(0));
  EXPECT_NEAR(in_line_closer(0) / in_line(0), 0.01, 0.002);  // proportional to the gap squared

  // The reducer keeps the geometry: from one place it reads A and B in line with it and C at a
  // right angle; with room for two, one of the pair in line goes, never C.
  LocalizationInformationReducer r(options(), kStdRange, kStdBearing);
  const std::map<LandmarkId, Eigen::Vector2d> where = {
      {1, {3.5, 0.5}}, {2, {3.6, 0.5}}, {3, {0.5, 3.6}}};
  r.observe(readings(0, {0.5, 0.5, 0}, {}, {1, 2, 3}, where));
  const auto lms = views({1, 2, 3});
  FakeBackend backend(lms);
  const std::vector<std::size_t> all = {0, 1, 2};
  const LandmarkId gone = r.choose({backend, lms, all, 1}).id;
  EXPECT_TRUE(gone == 1 || gone == 2) << gone;
}

TEST(LocalizationInformationReducer, LearnsItsReadingsThroughTheBudgetManager) {
  // The manager hands the reducer the step's readings with the landmark each went to; the place
  // then holds their information, and a dropped landmark leaves every place.
  BudgetOptions bo;
  bo.max_landmarks = 2;
  bo.protect_recent_steps = 0;
  BudgetManager manager(
      bo, std::make_unique<LocalizationInformationReducer>(options(), kStdRange, kStdBearing));
  FakeBackend b({budget_slam::testing::landmark(1, 1, 1, 0, 0),
                 budget_slam::testing::landmark(2, 1, 1, 0, 0),
                 budget_slam::testing::landmark(3, 1, 1, 0, 0)});
  b.pose = Pose2(0.5, 0.5, 0);
  const std::map<LandmarkId, Eigen::Vector2d> where = {
      {1, {3.5, 0.5}}, {2, {3.6, 0.5}}, {3, {0.5, 3.6}}};
  Step step;
  step.index = 0;
  step.scan.emplace();
  step.scan->max_range = 8;
  step.scan->fov_yaw = 2 * M_PI;
  for (LandmarkId id = 1; id <= 3; ++id) {
    const Eigen::Vector2d z = predictRangeBearing(b.pose, {0, 0, 0}, where.at(id)).z;
    step.scan->readings.push_back({id, z(0), z(1), 0});
    b.see(id, 0);
  }
  const auto drops = manager.enforce(b, step);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_TRUE(drops[0].id == 1 || drops[0].id == 2) << drops[0].id;
  EXPECT_EQ(drops[0].reducer, "localization-information");
}

TEST(LocalizationInformationReducer, ALandmarkThatComesBackCountsEveryPlaceItWasReadFrom) {
  // Landmark 9 is read at places 0-3 while it is not in the map (a refused newcomer, withheld
  // while it waits), then enters at place 4. On record, its loss counts the five places; with
  // remember_dropped = 0 only the place where it entered. Dropped again, it counts for nothing
  // (off the map) until it is back.
  const std::map<LandmarkId, Eigen::Vector2d> where = {{1, {2.5, 3}}, {9, {3, 6}}};
  const auto run = [&](std::size_t remember) {
    auto o = options();
    o.remember_dropped = remember;
    LocalizationInformationReducer r(o, kStdRange, kStdBearing);
    for (StepIndex k = 0; k < 4; ++k) {
      StepObservation seen = readings(k, {k + 0.5, 0.5, 0.7}, {}, {1}, where);
      const Eigen::Vector2d z = predictRangeBearing(seen.robot, {}, where.at(9)).z;
      seen.withheld.push_back({9, z(0), z(1)});
      r.observe(seen);
    }
    r.observe(readings(4, {4.5, 0.5, 0.7}, {}, {1, 9}, where));
    return r;
  };
  const auto remembered = run(1024), forgotten = run(0);
  LocalizationInformationReducer one(options(), kStdRange, kStdBearing);  // 9 at one place
  one.observe(readings(4, {4.5, 0.5, 0.7}, {}, {1, 9}, where));
  EXPECT_NEAR(forgotten.loss(9), one.loss(9), 1e-9);
  EXPECT_GT(remembered.loss(9), 3 * forgotten.loss(9));
  // The map without 9 is the same either way: readings on record change no place's information.
  EXPECT_NEAR(remembered.objective() - remembered.loss(9),
              forgotten.objective() - forgotten.loss(9), 1e-9);
  auto dropped = run(1024);
  dropped.forget(9);
  EXPECT_EQ(dropped.loss(9), 0.0);
  EXPECT_NEAR(dropped.objective(), remembered.objective() - remembered.loss(9), 1e-9);
}

TEST(LocalizationInformationReducer, TheManagerTellsTheReadingsItLeftOut) {
  // compete: newcomer 3 is refused at step 0; at step 1 its reading is left out of the processed
  // step (it waits), and the reducer is told it as withheld.
  struct Spy : public Reducer, public ObservationKeeper {
    std::string name() const override { return "spy"; }
    ReducerChoice choose(const DropContext& ctx) override {
      return {ctx.landmarks[ctx.candidates.back()].id, 0};  // the newest goes
    }
    void observe(const StepObservation& seen) override { withheld.push_back(seen.withheld); }
    void forget(LandmarkId) override {}
    std::vector<std::vector<Sighting>> withheld;
  };
  BudgetOptions bo;
  bo.max_landmarks = 2;
  bo.admission = BudgetOptions::Admission::Compete;
  auto spy = std::make_unique<Spy>();
  Spy* s = spy.get();
  BudgetManager manager(bo, std::move(spy));
  FakeBackend b({budget_slam::testing::landmark(1, 1, 1, 0, 0),
                 budget_slam::testing::landmark(2, 1, 1, 0, 0),
                 budget_slam::testing::landmark(3, 1, 1, 0, 0)});
  Step step;
  step.index = 0;
  step.scan.emplace();
  step.scan->readings = {{1, 2.0, 0.1, 0}, {2, 3.0, -0.2, 0}, {3, 4.0, 0.3, 0}};
  const auto drops = manager.enforce(b, step, step);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0].id, 3);
  EXPECT_EQ(drops[0].reason, "refused");
  Step next = step;
  next.index = 1;
  const Step processed = manager.admissible(next);
  ASSERT_EQ(processed.scan->readings.size(), 2u);  // 3 waits
  manager.enforce(b, processed, next);
  ASSERT_EQ(s->withheld.size(), 2u);
  EXPECT_TRUE(s->withheld[0].empty());
  ASSERT_EQ(s->withheld[1].size(), 1u);
  EXPECT_EQ(s->withheld[1][0].id, 3);
  EXPECT_DOUBLE_EQ(s->withheld[1][0].range, 4.0);
}

TEST(LocalizationInformationReducer, RegisteredWithItsSectionAndValidatedKeys) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("LocalizationInformationReducer", "objective", "min_log_det");
  ini.write("RangeBearingKFSLAM", "std_sensor_range", "0.03");
  const auto r = builtinReducers().create("localization-information", ini, 1);
  EXPECT_EQ(r->name(), "localization-information");
  EXPECT_NE(observationKeeper(r.get()), nullptr);
  mrpt::config::CConfigFileMemory bad;
  bad.write("LocalizationInformationReducer", "objective", "max");
  try {
    builtinReducers().create("localization-information", bad, 1);
    FAIL() << "objective = max was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("objective"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory bad_noise;
  bad_noise.write("RangeBearingKFSLAM", "std_sensor_range", "-0.1");
  EXPECT_THROW(builtinReducers().create("localization-information", bad_noise, 1), ConfigError);
}

namespace {

/// Landmarks 1-3 read from places 0-29 (robot along y = 0.5), then at step 30, from place 30, the
/// landmarks `last` (newcomer 9 among them, 12 m away: it enters at step 30). The reducer's choice
/// among every landmark of the map at that step.
LandmarkId newcomerCase(bool second_landmark_admission, const std::vector<LandmarkId>& last,
                        std::size_t* second_places = nullptr) {
  auto o = options();
  o.second_landmark_admission = second_landmark_admission;
  LocalizationInformationReducer r(o, kStdRange, kStdBearing);
  const std::map<LandmarkId, Eigen::Vector2d> where = {
      {1, {8, 3}}, {2, {15, 4}}, {3, {22, 3}}, {9, {31, 12}}};
  for (StepIndex k = 0; k < 30; ++k)
    r.observe(readings(k, {k + 0.5, 0.5, 0}, {}, {1, 2, 3}, where));
  r.observe(readings(30, {30.5, 0.5, 0}, {}, last, where));
  if (second_places) *second_places = r.secondLandmarkPlaces(9);
  std::vector<LandmarkView> lms;
  for (const LandmarkId id : {1, 2, 3})
    lms.push_back(budget_slam::testing::landmark(id, 1, 1, 0, 30));
  lms.push_back(budget_slam::testing::landmark(9, 1, 1, 30, 30));  // the newcomer
  FakeBackend backend(lms);
  const std::vector<std::size_t> all = {0, 1, 2, 3};
  return r.choose({backend, lms, all, 30}).id;
}

}  // namespace

TEST(LocalizationInformationReducer, ANewcomerThatIsAPlacesSecondLandmarkIsAdmittedWithTheOption) {
  // Newcomer 9 is read from one place, with landmark 1 alone of the map: it is that place's second
  // landmark. The objective refuses it (its loss, 9.9 nats from one place, is the least: 1-3 lose
  // 33-72 over thirty), the option admits it and drops the established landmark of least loss
  // instead (2 or 3: 1 is the other landmark of the place).
  std::size_t second = 0;
  EXPECT_EQ(newcomerCase(false, {1, 9}, &second), 9);
  EXPECT_EQ(second, 1u);
  const LandmarkId gone = newcomerCase(true, {1, 9});
  EXPECT_TRUE(gone == 2 || gone == 3) << gone;
  // Read with 1 and 2, it would be the place's third landmark: refused either way.
  EXPECT_EQ(newcomerCase(false, {1, 2, 9}, &second), 9);
  EXPECT_EQ(second, 0u);
  EXPECT_EQ(newcomerCase(true, {1, 2, 9}), 9);
}

TEST(LocalizationInformationReducer, WhenEveryCandidateIsASecondLandmarkTheObjectiveDecides) {
  // Two newcomers, each the second landmark of its own place, are the only candidates: one must
  // go, and it is the one the objective alone would drop.
  const std::map<LandmarkId, Eigen::Vector2d> where = {
      {1, {2, 3}}, {2, {9, 3}}, {7, {3, 5}}, {8, {8.5, 9}}};
  for (const bool option : {false, true}) {
    auto o = options();
    o.second_landmark_admission = option;
    LocalizationInformationReducer r(o, kStdRange, kStdBearing);
    r.observe(readings(0, {1.5, 0.5, 0}, {}, {1, 7}, where));
    r.observe(readings(0, {8.5, 0.5, 0}, {}, {2, 8}, where));
    EXPECT_EQ(r.secondLandmarkPlaces(7), 1u);
    EXPECT_EQ(r.secondLandmarkPlaces(8), 1u);
    std::vector<LandmarkView> lms;
    for (const LandmarkId id : {1, 2})
      lms.push_back(budget_slam::testing::landmark(id, 1, 1, 0, 0));
    for (const LandmarkId id : {7, 8})
      lms.push_back(budget_slam::testing::landmark(id, 1, 1, 0, 0));
    FakeBackend backend(lms);
    const std::vector<std::size_t> newcomers = {2, 3};
    const LandmarkId gone = r.choose({backend, lms, newcomers, 0}).id;
    EXPECT_EQ(gone, r.loss(7) < r.loss(8) ? 7 : 8) << "option " << option;
  }
}

TEST(LocalizationInformationReducer, SecondLandmarkAdmissionThroughTheManagerUnderCompete) {
  // The same case as the manager plays it, cap 3, admission = compete: with the option the
  // newcomer stays and an established landmark goes over the cap (no refusal).
  const std::map<LandmarkId, Eigen::Vector2d> where = {
      {1, {8, 3}}, {2, {15, 4}}, {3, {22, 3}}, {9, {31, 12}}};
  for (const bool option : {false, true}) {
    auto o = options();
    o.second_landmark_admission = option;
    BudgetOptions bo;
    bo.max_landmarks = 3;
    bo.protect_recent_steps = 0;
    bo.admission = BudgetOptions::Admission::Compete;
    BudgetManager manager(
        bo, std::make_unique<LocalizationInformationReducer>(o, kStdRange, kStdBearing));
    FakeBackend b({budget_slam::testing::landmark(1, 1, 1, 0, 0),
                   budget_slam::testing::landmark(2, 1, 1, 0, 0),
                   budget_slam::testing::landmark(3, 1, 1, 0, 0)});
    const auto play = [&](StepIndex k, const std::vector<LandmarkId>& ids) {
      b.pose = Pose2(k + 0.5, 0.5, 0);
      Step step;
      step.index = k;
      step.scan.emplace();
      step.scan->max_range = 20;
      step.scan->fov_yaw = 2 * M_PI;
      for (const LandmarkId id : ids) {
        const Eigen::Vector2d z = predictRangeBearing(b.pose, {0, 0, 0}, where.at(id)).z;
        step.scan->readings.push_back({id, z(0), z(1), 0});
        b.see(id, k);
      }
      return manager.enforce(b, step);
    };
    for (StepIndex k = 0; k < 30; ++k) EXPECT_TRUE(play(k, {1, 2, 3}).empty());
    b.add(budget_slam::testing::landmark(9, 1, 1, 30, 30));
    const auto drops = play(30, {1, 9});
    ASSERT_EQ(drops.size(), 1u);
    if (option) {
      EXPECT_TRUE(drops[0].id == 2 || drops[0].id == 3) << drops[0].id;
      EXPECT_EQ(drops[0].reason, "over_cap");
    } else {
      EXPECT_EQ(drops[0].id, 9);
      EXPECT_EQ(drops[0].reason, "refused");
    }
  }
}
