// budget-slam localize with no start pose (--wake-up, or none to be had): hand-made worlds written
// as real files (a rawlog, its ground truth and sidecar by budget-slam's dataset writers, a map
// folder by its run-file writers). Found by id within 10 steps and then tracked; a mirror-symmetric
// layout without ids, and a map of another world, reported as not found, never as a pose.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "AppTestUtil.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/dataset/DatasetFiles.h"
#include "budget_slam/dataset/StepToMrpt.h"
#include "budget_slam/report/RunFiles.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kConfig = kRoot + "/config.ini";
constexpr double kDeg = M_PI / 180;

struct Landmark {
  LandmarkId id;
  Eigen::Vector2d p;
};

/// A 20 m x 12 m room with landmarks placed without any symmetry.
std::vector<Landmark> room() {
  return {{10, {0.5, 0.8}},  {11, {3.2, -0.4}}, {12, {6.1, 1.7}},  {13, {9.4, 0.2}},
          {14, {13.0, 2.9}}, {15, {17.8, 1.1}}, {16, {19.2, 6.3}}, {17, {15.5, 10.4}},
          {18, {11.1, 8.8}}, {19, {7.3, 11.5}}, {20, {2.6, 9.9}},  {21, {-0.3, 5.2}},
          {22, {5.0, 5.6}},  {23, {9.9, 4.4}},  {24, {14.2, 6.8}}, {25, {12.4, 12.2}}};
}

/// Symmetric about both axes (so about the centre too): a pose and its half-turn about the centre
/// read the same.
std::vector<Landmark> mirrorRoom() {
  std::vector<Landmark> w;
  LandmarkId id = 1;
  for (const double x : {-6.0, -2.5, 2.5, 6.0})
    for (const double y : {-3.0, 3.0}) w.push_back({id++, {x, y}});
  w.push_back({id++, {-4.5, 0}});
  w.push_back({id++, {4.5, 0}});
  return w;
}

struct Sensor {
  double max_range = 8, fov = M_PI, std_range = 0.05, std_yaw = 0.5 * kDeg;
  bool with_ids = true;
};

/// `n` poses from `start`, `step` metres apart, turning `turn` radians a step.
std::vector<Pose2> arcPath(const Pose2& start, std::size_t n, double step, double turn) {
  std::vector<Pose2> p = {start};
  while (p.size() < n) p.push_back(compose(p.back(), Pose2(step, 0, turn)));
  return p;
}

/// Writes DIR/NAME.rawlog (one step a pose: noisy odometry, noisy readings of every landmark in
/// range and view), its sidecar ini and, with `truth`, its ground truth, through the dataset
/// writers; returns the rawlog's path.
std::string writeTraversal(const fs::path& dir, const std::string& name,
                           const std::vector<Pose2>& path, const std::vector<Landmark>& world,
                           const Sensor& sensor, bool truth, unsigned seed) {
  fs::create_directories(dir);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  dataset::ConvertedDataset d;
  const double odo_xy = 0.01, odo_yaw = 0.2 * kDeg;
  for (std::size_t k = 0; k < path.size(); ++k) {
    std::optional<OdometryIncrement> odo;
    if (k > 0) {
      const Pose2 u = between(path[k - 1], path[k]);
      odo.emplace();
      odo->mean = Pose2(u.x + odo_xy * g(rng), u.y + odo_xy * g(rng), u.phi + odo_yaw * g(rng));
      odo->cov = Eigen::Vector3d(odo_xy * odo_xy, odo_xy * odo_xy, odo_yaw * odo_yaw).asDiagonal();
    }
    RangeBearingScan scan;
    scan.min_range = 0.1;
    scan.max_range = sensor.max_range;
    scan.fov_yaw = sensor.fov;
    scan.std_range = sensor.std_range;
    scan.std_yaw = sensor.std_yaw;
    for (const auto& l : world) {
      const Eigen::Vector2d v = path[k].transformTo(l.p);
      const double r = v.norm(), b = std::atan2(v.y(), v.x());
      if (r > sensor.max_range || r < scan.min_range || std::abs(b) > sensor.fov / 2) continue;
      scan.readings.push_back({sensor.with_ids ? l.id : kNoLandmarkId,
                               r + sensor.std_range * g(rng),
                               wrapAngle(b + sensor.std_yaw * g(rng)), 0});
    }
    d.steps.push_back(dataset::makeStep(k, 1.0 + static_cast<double>(k), odo, scan));
    if (truth) d.ground_truth.path.push_back(path[k]);
  }
  if (truth)
    for (const auto& l : world) d.ground_truth.landmarks[l.id] = l.p;
  d.noise = {sensor.std_range, sensor.std_yaw, 0.1, sensor.max_range, sensor.fov, {}};
  d.notes = {"hand-made traversal for the wake-up tests"};
  const std::string rawlog = (dir / (name + ".rawlog")).string();
  dataset::saveDataset(d, rawlog);
  return rawlog;
}

/// A map folder as `run` leaves it: landmarks.csv (marginals of 5 cm) and, with `aligned`, a
/// summary.json whose ground_truth.map_alignment is the identity (the map's frame is the world's).
fs::path writeMap(const fs::path& dir, const std::vector<Landmark>& world, bool aligned) {
  fs::create_directories(dir);
  std::vector<LandmarkView> views;
  for (const auto& l : world) {
    LandmarkView v;
    v.id = l.id;
    v.mean = l.p;
    v.cov = Eigen::Matrix2d::Identity() * 0.05 * 0.05;
    v.n_obs = 5;
    views.push_back(v);
  }
  report::writeLandmarksCsv((dir / "landmarks.csv").string(), views);
  if (aligned)
    report::writeSummaryJson(
        (dir / "summary.json").string(),
        {{"status", "ok"},
         {"ground_truth",
          {{"map_alignment", {{"x", 0.0}, {"y", 0.0}, {"yaw", 0.0}, {"source", "landmarks"}}}}}});
  return dir;
}

std::vector<std::string> localizeArgs(const fs::path& map, const std::string& rawlog,
                                      const fs::path& out) {
  return {"localize", "-c", kConfig, "--map", map.string(), "-i", rawlog, "-o", out.string()};
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

const std::string kNotFound = "budget-slam: error: wake-up: the robot was not found on the map in ";

}  // namespace

// Known ids: found from the first steps within 0.25 m / 5 deg of the ground truth, then the rest of
// the traversal is localized from there (tracked: every scored step within the success bounds).
TEST(LocalizeWakeUp, KnownIdsFoundWithinTenStepsThenTracked) {
  const auto dir = freshDir("localize_wake_ids");
  const auto path = arcPath(Pose2(10, 2, 0), 80, 0.3, 0.05);
  const auto rawlog = writeTraversal(dir / "data", "room", path, room(), Sensor{}, true, 5);
  const auto map = writeMap(dir / "map", room(), true);
  const auto r = runApp(plus(localizeArgs(map, rawlog, dir / "out"), {"--wake-up"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("start from wake-up\nwoken up at step "), std::string::npos) << r.out;
  const auto j = readJson(dir / "out" / "summary.json");
  const auto& w = j["wake_up"];
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(w["requested"], "--wake-up");
  EXPECT_TRUE(w["found"]);
  EXPECT_EQ(w["status"], "found");
  EXPECT_EQ(w["why_not_found"], "");
  EXPECT_EQ(w["correspondence"], "ids");
  const int used = w["steps_used"].get<int>();
  EXPECT_GE(used, 1);
  EXPECT_LE(used, 10);
  EXPECT_EQ(w["step"], used - 1);
  EXPECT_GE(w["time_ms"].get<double>(), 0.0);
  EXPECT_GE(w["landmarks"].get<int>(), 2);
  EXPECT_EQ(w["error"]["against"], "ground_truth");
  EXPECT_LT(w["error"]["xy_m"].get<double>(), 0.25);
  EXPECT_LT(w["error"]["yaw_deg"].get<double>(), 5.0);
  EXPECT_TRUE(w["error"]["within_success"]);
  const Pose2& t = path[static_cast<std::size_t>(used - 1)];
  EXPECT_NEAR(w["pose"]["x"].get<double>(), t.x, 0.25);
  EXPECT_NEAR(w["pose"]["y"].get<double>(), t.y, 0.25);
  EXPECT_GT(w["cov"][0][0].get<double>(), 0.0);
  // The filter starts where the robot was found, with the wake-up's covariance.
  EXPECT_EQ(j["start_pose"]["source"], "wake-up");
  EXPECT_DOUBLE_EQ(j["start_pose"]["x"].get<double>(), w["pose"]["x"].get<double>());
  // The rest of the traversal is localized and tracked.
  EXPECT_EQ(j["counts"]["steps"], 80 - used);
  const auto& loc = j["localization"];
  EXPECT_EQ(loc["steps_compared"], 80 - used);
  EXPECT_LT(loc["rmse_m"].get<double>(), 0.25);
  EXPECT_EQ(loc["steps_lost"], 0);
  EXPECT_EQ(loc["diverged_at_step"], nullptr);
  const auto rows = readCsv(dir / "out" / "steps.csv");
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(80 - used));
  EXPECT_EQ(rows.front()[0], std::to_string(used));

  // Found at the last step there is: nothing left to localize, said without a warning.
  const auto last = runApp(
      plus(localizeArgs(map, rawlog, dir / "last"), {"--wake-up", "--quiet", "--max-steps", "1"}));
  ASSERT_EQ(last.exit_code, 0) << last.err;
  EXPECT_EQ(last.err, "");
  const auto jl = readJson(dir / "last" / "summary.json");
  EXPECT_TRUE(jl["wake_up"]["found"]);
  EXPECT_EQ(jl["wake_up"]["steps_used"], 1);
  EXPECT_EQ(jl["counts"]["steps"], 0);

  // Without --wake-up, the ground truth gives the start: no wake_up block.
  const auto g = runApp(plus(localizeArgs(map, rawlog, dir / "gt"), {"--quiet"}));
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const auto jg = readJson(dir / "gt" / "summary.json");
  EXPECT_EQ(jg["start_pose"]["source"], "ground truth");
  EXPECT_FALSE(jg.contains("wake_up"));

  // A start pose and --wake-up contradict each other: a bad command line.
  const auto both =
      runApp(plus(localizeArgs(map, rawlog, dir / "both"), {"--wake-up", "--start-pose", "1,2,3"}));
  EXPECT_EQ(both.exit_code, kExitBadCommandLine);
  EXPECT_EQ(both.err,
            "budget-slam: --wake-up: not with --start-pose (a start pose is not looked for); see "
            "budget-slam localize --help\n");
  EXPECT_FALSE(fs::exists(dir / "both"));
}

// A map without ground truth and no --start-pose: there is no start pose to be had, so localize
// wakes up by itself (and says so). Without ids, a layout symmetric under a half-turn reads the
// same from two poses: not found (ambiguous), exit 3, summary.json says why, and no pose.
TEST(LocalizeWakeUp, MirrorSymmetricMapWithoutIdsIsNotFoundNeverAPose) {
  const auto dir = freshDir("localize_wake_mirror");
  Sensor s;
  s.with_ids = false;
  s.fov = 2 * M_PI;
  s.max_range = 20;
  const auto rawlog = writeTraversal(
      dir / "data", "mirror", arcPath(Pose2(1.0, 0.5, 0.3), 30, 0.3, 0), mirrorRoom(), s, false, 3);
  const auto map = writeMap(dir / "map", mirrorRoom(), false);
  const auto r = runApp(localizeArgs(map, rawlog, dir / "out"));
  EXPECT_EQ(r.exit_code, kExitNotFound);
  EXPECT_EQ(r.err.rfind("budget-slam: no start pose (no --start-pose, no ground truth in the "
                        "map's frame, no --reference-trajectory): waking up on the map\n" +
                            kNotFound + "10 steps (ambiguous: ",
                        0),
            0u)
      << r.err;
  EXPECT_NE(r.err.find(" with another); no pose is guessed\n"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2);
  EXPECT_EQ(r.out, "");
  const auto j = readJson(dir / "out" / "summary.json");
  EXPECT_EQ(j["status"], "not_found");
  EXPECT_EQ(j["started"], false);
  const auto& w = j["wake_up"];
  EXPECT_EQ(w["requested"], "no start pose");
  EXPECT_FALSE(w["found"]);
  EXPECT_EQ(w["status"], "ambiguous");
  EXPECT_EQ(w["correspondence"], "search");
  EXPECT_EQ(w["steps_used"], 10);
  EXPECT_EQ(w["pose"], nullptr);
  EXPECT_EQ(w["cov"], nullptr);
  EXPECT_EQ(w["runner_up_landmarks"], w["landmarks"]);  // the twin agrees as well
  EXPECT_EQ(j["error"].get<std::string>(),
            w["why_not_found"].get<std::string>() + "; no pose is guessed");
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.tum"));
  EXPECT_FALSE(fs::exists(dir / "out" / "steps.csv"));
}

// The map of another world: by id (the ids repeat, the places do not) and by search, not found.
TEST(LocalizeWakeUp, MapOfAnotherWorldIsNotFound) {
  const auto dir = freshDir("localize_wake_wrong_world");
  const auto path = arcPath(Pose2(10, 2, 0), 30, 0.3, 0.05);
  for (const unsigned seed : {23u, 29u, 31u, 37u}) {
    // The room's ids at other places of the same extent.
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 20);
    std::vector<Landmark> other;
    for (const auto& l : room()) other.push_back({l.id, {u(rng), u(rng) * 0.6}});
    const auto map = writeMap(dir / ("map" + std::to_string(seed)), other, true);
    for (const bool ids : {true, false}) {
      Sensor s;
      s.with_ids = ids;
      const std::string name = (ids ? "ids" : "noids") + std::to_string(seed);
      const auto rawlog = writeTraversal(dir / "data", name, path, room(), s, true, seed);
      const auto r =
          runApp(plus(localizeArgs(map, rawlog, dir / ("out_" + name)), {"--wake-up", "--quiet"}));
      EXPECT_EQ(r.exit_code, kExitNotFound) << name << ": " << r.err;
      EXPECT_EQ(r.err.rfind(kNotFound + "10 steps (", 0), 0u) << r.err;
      const auto j = readJson(dir / ("out_" + name) / "summary.json");
      EXPECT_EQ(j["status"], "not_found");
      EXPECT_FALSE(j["wake_up"]["found"]) << name;
      EXPECT_EQ(j["wake_up"]["correspondence"], ids ? "ids" : "search");
      EXPECT_EQ(j["wake_up"]["pose"], nullptr);
    }
  }
}
