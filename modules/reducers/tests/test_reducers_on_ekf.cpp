#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <map>
#include <set>

#include "TestStates.h"
#include "budget_slam/core/StepFilter.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/MutualInformationReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::testing::bruteForceGains;

namespace {

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
const std::string kDemo = kRoot + "/rawlogs/kf-slam_demo.rawlog";
const std::string kIni = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";

const std::vector<Step>& demoSteps() {
  static const std::vector<Step> steps = dataset::readAllSteps(kDemo);
  return steps;
}

/// The EKF's full covariance through the Backend interface: robot, then landmarks in view order.
Eigen::MatrixXd fullCovariance(const Backend& b, StepIndex step, std::vector<LandmarkId>* ids) {
  std::vector<VariableKey> vars = {VariableKey::pose(step)};
  ids->clear();
  for (const auto& l : b.landmarks()) {
    vars.push_back(VariableKey::landmark(l.id));
    ids->push_back(l.id);
  }
  return b.jointCovariance(vars);
}

double tol(double x) { return 1e-9 * std::max(1.0, std::abs(x)); }

/// Runs the demo under `reducer` with a cap; returns the eviction sequence.
std::vector<Eviction> runDemo(const std::string& reducer, std::size_t cap,
                              const mrpt::config::CConfigFileBase& extra, std::size_t* max_seen,
                              std::set<LandmarkId>* readmitted = nullptr) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  BudgetOptions o;
  o.max_landmarks = cap;
  BudgetManager manager(o, builtinReducers().create(reducer, extra, 1));
  std::vector<Eviction> all;
  *max_seen = 0;
  for (const Step& raw : demoSteps()) {
    const Step s =
        manager.options().readmit_evicted ? raw : withoutReadingsOf(raw, manager.evicted());
    backend.process(s);
    for (auto& e : manager.enforce(backend, raw.index)) all.push_back(e);
    *max_seen = std::max(*max_seen, backend.landmarkCount());
    if (readmitted)
      for (const auto& l : backend.landmarks())
        if (manager.evicted().count(l.id)) readmitted->insert(l.id);
  }
  for (auto& e : manager.finish(backend, demoSteps().back().index)) all.push_back(e);
  return all;
}

}  // namespace

TEST(ReducersOnEkf, MiScoresEqualBruteForceOnRealFilterStates) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  MutualInformationReducer mi{MutualInformationOptions()};
  std::size_t checked = 0;
  for (const Step& s : demoSteps()) {
    backend.process(s);
    if (s.index % 10 != 9 || backend.landmarkCount() < 2) continue;
    if (backend.robotPose().cov.diagonal().minCoeff() <= 0) continue;  // before the first motion
    std::vector<LandmarkId> ids;
    const Eigen::MatrixXd P = fullCovariance(backend, s.index, &ids);
    const auto brute = bruteForceGains(P);
    const auto gains = backend.informationGain(ids);
    for (std::size_t i = 0; i < ids.size(); ++i)
      EXPECT_NEAR(gains[i], brute[i], tol(brute[i])) << "step " << s.index << " id " << ids[i];
    const auto lms = backend.landmarks();
    std::vector<std::size_t> cand(lms.size());
    std::iota(cand.begin(), cand.end(), 0);
    const auto c = mi.choose({backend, lms, cand, s.index});
    const auto lowest = std::min_element(brute.begin(), brute.end()) - brute.begin();
    EXPECT_EQ(c.id, ids[lowest]) << "step " << s.index;
    EXPECT_NEAR(c.score, brute[lowest], tol(brute[lowest]));
    ++checked;
  }
  EXPECT_GE(checked, 20u);
}

TEST(ReducersOnEkf, SuccessiveDropsOfOneEventEqualAFreshComputation) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  for (const Step& s : demoSteps()) backend.process(s);
  const StepIndex last = demoSteps().back().index;
  ASSERT_EQ(backend.landmarkCount(), 70u);
  // Twelve drops after one step: the backend's gains come from one factorization and Schur
  // updates; the reference factorizes the reduced covariance afresh each time.
  for (int k = 0; k < 12; ++k) {
    std::vector<LandmarkId> ids;
    const Eigen::MatrixXd P = fullCovariance(backend, last, &ids);
    const auto brute = bruteForceGains(P);
    const auto gains = backend.informationGain(ids);
    for (std::size_t i = 0; i < ids.size(); ++i)
      ASSERT_NEAR(gains[i], brute[i], tol(brute[i])) << "after " << k << " drops, id " << ids[i];
    backend.removeLandmark(ids[std::min_element(gains.begin(), gains.end()) - gains.begin()]);
  }
}

TEST(ReducersOnEkf, ObjectiveModeOnTheFinalFilterStateMatchesBruteForce) {
  // Alg. 3 after the last step of the demo, no cap: what the reducer drops is what a brute-force
  // evaluation of the objective on the final covariance says (pose lag P = 5). On the EKF no
  // gain is near 0, so at lambda = 0.4 the first drop already raises rho (0.40 -> 0.54) and
  // nothing goes; at lambda = 0.95 the sequence runs a good way.
  std::map<double, std::size_t> dropped;
  for (const double lambda : {0.4, 0.95}) {
    mrpt::config::CConfigFile ini(kIni);
    ekf::EkfBackend backend(ini);
    for (const Step& s : demoSteps()) backend.process(s);
    const StepIndex last = demoSteps().back().index;
    std::vector<LandmarkId> ids;
    const Eigen::MatrixXd P = fullCovariance(backend, last, &ids);
    std::vector<bool> candidate;
    for (const auto& l : backend.landmarks()) candidate.push_back(last - l.last_step >= 5);
    const auto expected = budget_slam::testing::bruteForceObjective(P, ids, candidate, lambda);

    MutualInformationOptions o;
    o.mode = MutualInformationOptions::Mode::Objective;
    o.lambda = lambda;
    BudgetOptions b;
    b.max_landmarks = 1000;
    BudgetManager manager(b, std::make_unique<MutualInformationReducer>(o));
    const auto drops = manager.finish(backend, last);
    ASSERT_EQ(drops.size(), expected.size()) << "lambda " << lambda;
    for (std::size_t i = 0; i < drops.size(); ++i) {
      EXPECT_EQ(drops[i].id, expected[i].first);
      EXPECT_NEAR(drops[i].score, expected[i].second, tol(expected[i].second));
      EXPECT_EQ(drops[i].reason, "objective");
    }
    EXPECT_EQ(backend.landmarkCount(), 70u - expected.size());
    std::printf("lambda %.1f: objective mode drops %zu of 70 landmarks\n", lambda, expected.size());
  }
}

TEST(ReducersOnEkf, EveryReducerKeepsTheCapAndIsDeterministic) {
  mrpt::config::CConfigFileMemory extra;
  for (const std::string name : {"mi", "coverage", "coverage-mi", "info-content"}) {
    std::size_t max_a = 0, max_b = 0;
    const auto a = runDemo(name, 20, extra, &max_a);
    const auto b = runDemo(name, 20, extra, &max_b);
    EXPECT_LE(max_a, 20u) << name;
    EXPECT_GE(a.size(), 50u) << name;  // the demo maps 70 landmarks
    ASSERT_EQ(a.size(), b.size()) << name;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].id, b[i].id) << name;
  }
}

TEST(ReducersOnEkf, IncrementalModeNeverReadmitsAndRunsEveryPsiSteps) {
  mrpt::config::CConfigFileMemory extra;
  extra.write("MutualInformationReducer", "mode", "incremental");
  extra.write("MutualInformationReducer", "psi", "50");
  extra.write("MutualInformationReducer", "lambda", "0.8");
  std::size_t max_seen = 0;
  std::set<LandmarkId> readmitted;
  const auto drops = runDemo("mi", 1000, extra, &max_seen, &readmitted);
  EXPECT_TRUE(readmitted.empty());
  ASSERT_FALSE(drops.empty());
  for (const auto& e : drops) {
    EXPECT_EQ(e.reason, "incremental");
    EXPECT_EQ((e.step + 1) % 50, 0u) << e.step;
  }
}
