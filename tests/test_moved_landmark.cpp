// A scripted world where one landmark moves by 1 m between two sessions (budget-simulate's
// sessions, `run --resume --wake-up`): with [LandmarkBudget] moved_landmarks = split the landmark
// is split (the old estimate leaves the map as moved, the same id starts again at its new place),
// the landmarks around it stay within their noise and nothing else is split; with it off, its
// readings are fused and drag the estimate between the two places (docs/ALGORITHMS.md "Moved
// landmarks").
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <map>

#include "AppTestUtil.h"
#include "budget_slam/dataset/Sessions.h"

namespace budget_slam::testing {
namespace {

struct Landmark {
  Eigen::Vector2d mean;
  Eigen::Matrix2d cov;
  std::size_t first_step = 0;
};

std::map<LandmarkId, Landmark> landmarksOf(const std::filesystem::path& csv) {
  const CsvTable t = readCsvTable(csv);
  std::map<LandmarkId, Landmark> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    Landmark l;
    l.mean = Eigen::Vector2d(std::stod(t.at(r, "x")), std::stod(t.at(r, "y")));
    const double xy = std::stod(t.at(r, "cov_xy"));
    l.cov << std::stod(t.at(r, "cov_xx")), xy, xy, std::stod(t.at(r, "cov_yy"));
    l.first_step = std::stoul(t.at(r, "first_step"));
    out[std::stol(t.at(r, "id"))] = l;
  }
  return out;
}

/// (landmark_id, reason) of every row of an evictions.csv.
std::vector<std::pair<LandmarkId, std::string>> evictionsOf(const std::filesystem::path& csv) {
  const CsvTable t = readCsvTable(csv);
  std::vector<std::pair<LandmarkId, std::string>> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r)
    out.emplace_back(std::stol(t.at(r, "landmark_id")), t.at(r, "reason"));
  return out;
}

/// The world: `rooms`, seed 2001, two sessions, one landmark of 155 moved by 1 m before the
/// second (change 0.006, split 0:1:0); written into `dir`, as two session rawlogs or, `joined`,
/// as one rawlog of both (budget-simulate --joined).
struct MovedWorld {
  std::filesystem::path s1, s2;  ///< the session rawlogs; `joined`: s1 is the one rawlog
  LandmarkId id = kNoLandmarkId;
  Eigen::Vector2d before, after;
};

MovedWorld makeWorld(const std::filesystem::path& dir, bool joined) {
  std::filesystem::create_directories(dir);
  dataset::SimulationOptions sim;
  sim.scenario = dataset::SimulationOptions::ScenarioKind::Rooms;
  sim.seed = 2001;
  dataset::SessionChangeOptions sessions;
  sessions.sessions = 2;
  sessions.change = 0.006;
  sessions.share_disappear = 0;
  sessions.share_appear = 0;
  sessions.joined = joined;
  const std::string rawlog = (dir / "life.rawlog").string();
  dataset::simulateSessionsToFiles(sim, sessions, rawlog);
  MovedWorld w;
  w.s1 = joined ? rawlog : dataset::sessionRawlogName(rawlog, 1, 2);
  if (!joined) w.s2 = dataset::sessionRawlogName(rawlog, 2, 2);
  const CsvTable changes = readCsvTable(dataset::changesFileFor(rawlog));
  EXPECT_EQ(changes.rows.size(), 1u);
  if (changes.rows.size() != 1) return w;
  EXPECT_EQ(changes.at(0, "change"), "moved");
  w.id = std::stol(changes.at(0, "id"));
  w.before =
      Eigen::Vector2d(std::stod(changes.at(0, "x_before")), std::stod(changes.at(0, "y_before")));
  w.after =
      Eigen::Vector2d(std::stod(changes.at(0, "x_after")), std::stod(changes.at(0, "y_after")));
  return w;
}

/// Both sessions with reducer none and no cap (every landmark kept), `mode` the moved_landmarks
/// value; returns the second session's folder.
std::filesystem::path runSessions(const MovedWorld& w, const std::filesystem::path& dir,
                                  const std::string& mode, const std::string& backend) {
  const std::vector<std::string> common = {"-c",
                                           kRoot + "/config.ini",
                                           "--reducer",
                                           "none",
                                           "--cap",
                                           "none",
                                           "--backend",
                                           backend,
                                           "--quiet",
                                           "--set",
                                           "LandmarkBudget.moved_landmarks=" + mode};
  std::vector<std::string> a = {"run", "-i", w.s1.string(), "-o", (dir / "s1").string()};
  a.insert(a.end(), common.begin(), common.end());
  const AppResult r1 = runApp(a);
  EXPECT_EQ(r1.exit_code, 0) << r1.err;
  std::vector<std::string> b = {"run",
                                "-i",
                                w.s2.string(),
                                "-o",
                                (dir / "s2").string(),
                                "--resume",
                                (dir / "s1").string(),
                                "--wake-up"};
  b.insert(b.end(), common.begin(), common.end());
  const AppResult r2 = runApp(b);
  EXPECT_EQ(r2.exit_code, 0) << r2.err;
  return dir / "s2";
}

/// Each test has its own folder and world: ctest runs the tests of this file as separate processes
/// side by side, so nothing is shared between them.
class MovedLandmarkSessions : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = freshDir(std::string("moved_landmark/") + info->name());
  }
  std::filesystem::path dir_;
};

/// The split: exactly one row `moved`, of the moved id, in session 2; the same id in the map again
/// as a newcomer of session 2 (first_step in it) at its new place; the old estimate had stood at
/// the old place. Every landmark within 4 m of it moved less than its own noise between the
/// sessions (d^2 under the session-1 covariance below the 99.9% gate).
void expectSplit(const MovedWorld& w, const std::filesystem::path& s1,
                 const std::filesystem::path& s2) {
  const auto rows = evictionsOf(s2 / "evictions.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0], std::make_pair(w.id, std::string("moved")));
  EXPECT_TRUE(evictionsOf(s1 / "evictions.csv").empty());
  const auto one = landmarksOf(s1 / "landmarks.csv");
  const auto two = landmarksOf(s2 / "landmarks.csv");
  ASSERT_TRUE(one.count(w.id) && two.count(w.id));
  EXPECT_LT((one.at(w.id).mean - w.before).norm(), 0.1);
  EXPECT_LT((two.at(w.id).mean - w.after).norm(), 0.15);  // not dragged from the old place
  const std::size_t session_start = std::stoul(readCsvTable(s2 / "steps.csv").rows.at(0).at(0));
  EXPECT_GE(two.at(w.id).first_step, session_start);  // a newcomer of session 2
  EXPECT_EQ(one.size(), two.size());
  std::size_t near = 0;
  for (const auto& [id, l] : one) {
    if (id == w.id || (l.mean - one.at(w.id).mean).norm() > 4) continue;
    ASSERT_TRUE(two.count(id));
    ++near;
    const Eigen::Vector2d d = two.at(id).mean - l.mean;
    EXPECT_LT(d.dot(l.cov.ldlt().solve(d)), 13.8155) << "landmark " << id;
  }
  EXPECT_GE(near, 10u);
}

TEST_F(MovedLandmarkSessions, SplitNotFusedOnTheEkf) {
  const MovedWorld world = makeWorld(dir_ / "world", false);
  ASSERT_NE(world.id, kNoLandmarkId);
  const auto s2 = runSessions(world, dir_, "split", "ekf");
  expectSplit(world, dir_ / "s1", s2);
  // The suspects go with the session: a second session saves its record too.
  EXPECT_NE(slurp(s2 / "session_state.txt").find("moved_landmarks"), std::string::npos);
}

TEST_F(MovedLandmarkSessions, FusedWhenOffDragsTheEstimate) {
  const MovedWorld world = makeWorld(dir_ / "world", false);
  ASSERT_NE(world.id, kNoLandmarkId);
  const auto s2 = runSessions(world, dir_, "off", "ekf");
  EXPECT_TRUE(evictionsOf(s2 / "evictions.csv").empty());
  const auto two = landmarksOf(s2 / "landmarks.csv");
  ASSERT_TRUE(two.count(world.id));
  // Between the two places, far from both: the old estimate took in the new readings.
  EXPECT_GT((two.at(world.id).mean - world.after).norm(), 0.3);
  EXPECT_GT((two.at(world.id).mean - world.before).norm(), 0.2);
}

// The graph backend after `run --resume --wake-up`: the second session starts a new graph on the
// saved map (each landmark under its prior, no pose yet), and the moved landmark leaves it and
// starts again, as on the EKF.
TEST_F(MovedLandmarkSessions, SplitNotFusedOnTheGraphAfterAResume) {
  const MovedWorld world = makeWorld(dir_ / "world", false);
  ASSERT_NE(world.id, kNoLandmarkId);
  const auto s2 = runSessions(world, dir_, "split", "graph");
  expectSplit(world, dir_ / "s1", s2);
}

// The graph backend, on the same two sessions driven as one process (budget-simulate --joined).
TEST_F(MovedLandmarkSessions, SplitNotFusedOnTheGraphInOneProcess) {
  const MovedWorld world = makeWorld(dir_ / "world", true);
  ASSERT_NE(world.id, kNoLandmarkId);
  const AppResult r =
      runApp({"run", "-c", kRoot + "/config.ini", "-i", world.s1.string(), "-o",
              (dir_ / "run").string(), "--reducer", "none", "--cap", "none", "--backend", "graph",
              "--quiet", "--set", "LandmarkBudget.moved_landmarks=split"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = evictionsOf(dir_ / "run" / "evictions.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0], std::make_pair(world.id, std::string("moved")));
  const auto lm = landmarksOf(dir_ / "run" / "landmarks.csv");
  ASSERT_TRUE(lm.count(world.id));
  EXPECT_LT((lm.at(world.id).mean - world.after).norm(), 0.15);
  EXPECT_GE(lm.at(world.id).first_step, 424u);  // started in the second session's lap
}

}  // namespace
}  // namespace budget_slam::testing
