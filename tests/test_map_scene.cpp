// map.3Dscene loaded back with MRPT's COpenGLScene API: every object is there, named, and matches
// the run's landmarks.csv, trajectory.tum, evictions.csv and ground truth files.
#include <gtest/gtest.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/opengl/CEllipsoid2D.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <algorithm>

#include <cmath>
#include <map>
#include <set>

#include "AppTestUtil.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/reducers/KMeans.h"
#include "budget_slam/report/MapScene.h"

namespace budget_slam::testing {
namespace {

namespace fs = std::filesystem;
namespace names = report::scene_names;
using namespace mrpt::opengl;

/// CRenderizable keeps object positions in single precision [m].
constexpr double kFloat = 1e-5;

/// Rows of a whitespace-separated numeric file, '#' and '%' lines skipped.
std::vector<std::vector<double>> readNumbers(const fs::path& p) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(slurp(p));
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") == std::string::npos ||
        line[line.find_first_not_of(" \t")] == '#' || line[line.find_first_not_of(" \t")] == '%')
      continue;
    std::istringstream ls(line);
    std::vector<double> row;
    for (double v; ls >> v;) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

template <class T>
std::shared_ptr<T> object(const COpenGLScene::Ptr& scene, const std::string& name) {
  auto o = std::dynamic_pointer_cast<T>(scene->getByName(name));
  EXPECT_TRUE(o) << "no " << name << " of the expected class in the scene";
  return o;
}

COpenGLScene::Ptr load(const fs::path& p) {
  auto scene = COpenGLScene::Create();
  EXPECT_TRUE(scene->loadFromFile(p.string())) << p;
  return scene;
}

/// Run of the kf-slam demo with the coverage reducer under cap 20: drops, clusters, ground truth.
const fs::path& coverageRun() {
  static const fs::path dir = [] {
    const auto d = freshDir("map_scene_coverage");
    const auto r = runApp({"run", "-c", kRoot + "/config.ini", "-i", kDemo, "-o", d.string(),
                           "--reducer", "coverage", "--cap", "20", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d;
  }();
  return dir;
}

TEST(MapScene, ObjectsMatchTheRunFiles) {
  const fs::path& dir = coverageRun();
  ASSERT_TRUE(fs::exists(dir / "map.3Dscene"));
  const auto scene = load(dir / "map.3Dscene");

  // Estimated trajectory: a segment a pair of consecutive trajectory.tum rows, same positions.
  const auto tum = readNumbers(dir / "trajectory.tum");
  ASSERT_EQ(tum.size(), 249u);
  auto path = object<CSetOfLines>(scene, names::kTrajectory);
  ASSERT_TRUE(path);
  ASSERT_EQ(path->getLineCount(), tum.size() - 1);
  for (std::size_t i = 0; i + 1 < tum.size(); ++i) {
    double x0, y0, z0, x1, y1, z1;
    path->getLineByIndex(i, x0, y0, z0, x1, y1, z1);
    EXPECT_NEAR(x0, tum[i][1], 1e-6);
    EXPECT_NEAR(y0, tum[i][2], 1e-6);
    EXPECT_NEAR(x1, tum[i + 1][1], 1e-6);
    EXPECT_NEAR(y1, tum[i + 1][2], 1e-6);
  }

  // Ground truth: the whole robot path and every landmark of the rawlog's files.
  const auto gt_path = readNumbers(kRoot + "/rawlogs/kf-slam_demo_ground_truth_robot_path.txt");
  const auto gt_landmarks = readNumbers(kRoot + "/rawlogs/kf-slam_demo_ground_truth.txt");
  auto gt = object<CSetOfLines>(scene, names::kGroundTruthPath);
  ASSERT_TRUE(gt);
  EXPECT_EQ(gt->getLineCount(), gt_path.size() - 1);
  auto gt_points = object<CPointCloud>(scene, names::kGroundTruthLandmarks);
  ASSERT_TRUE(gt_points);
  EXPECT_EQ(gt_points->size(), gt_landmarks.size());

  // Kept landmarks: one 2-sigma ellipse each, named by id and coverage cluster, at the mean of
  // landmarks.csv with its covariance, in map.png's colour of that cluster.
  const auto rows = readCsv(dir / "landmarks.csv");
  ASSERT_EQ(rows.size(), 20u);
  auto kept = object<CSetOfObjects>(scene, names::kKept);
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->size(), rows.size());
  auto centres = object<CPointCloudColoured>(scene, names::kKeptCentres);
  ASSERT_TRUE(centres);
  EXPECT_EQ(centres->size(), rows.size());

  std::vector<Eigen::Vector2d> obs_means;
  for (const auto& r : rows) obs_means.emplace_back(std::stod(r[7]), std::stod(r[8]));
  reducers::CoverageOptions coverage;  // config.ini's [CoverageReducer] is the default, seed 1
  const auto clusters = reducers::KMeans::cluster(obs_means, coverage.kmeans(obs_means.size()));
  std::set<std::size_t> distinct(clusters.label.begin(), clusters.label.end());
  EXPECT_EQ(distinct.size(), 5u);  // round(0.25 * 20)

  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const int cluster = static_cast<int>(clusters.label[i]);
    const std::string name = names::keptLandmark(std::stoll(r[0]), cluster);
    EXPECT_EQ(name, "landmark " + r[0] + ", coverage cluster " + std::to_string(cluster));
    auto e = object<CEllipsoid2D>(scene, name);
    ASSERT_TRUE(e);
    EXPECT_NEAR(e->getPoseX(), std::stod(r[1]), kFloat);
    EXPECT_NEAR(e->getPoseY(), std::stod(r[2]), kFloat);
    const auto cov = e->getCovMatrix();
    EXPECT_NEAR(cov(0, 0), std::stod(r[3]), 1e-12 + 1e-9 * std::abs(std::stod(r[3])));
    EXPECT_NEAR(cov(0, 1), std::stod(r[4]), 1e-12 + 1e-9 * std::abs(std::stod(r[4])));
    EXPECT_NEAR(cov(1, 1), std::stod(r[5]), 1e-12 + 1e-9 * std::abs(std::stod(r[5])));
    EXPECT_FLOAT_EQ(e->getQuantiles(), 2.0f);
    const auto rgb = report::clusterRgb(clusters.label[i]);
    EXPECT_EQ(e->getColorR_u8(), rgb[0]);
    EXPECT_EQ(e->getColorG_u8(), rgb[1]);
    EXPECT_EQ(e->getColorB_u8(), rgb[2]);
  }

  // Dropped landmarks: a cross (two segments) a row of evictions.csv.
  // Refused newcomers (admission = compete) never held a place: no cross, not counted as dropped.
  auto evictions = readCsv(dir / "evictions.csv");
  const std::size_t refused = evictions.size();
  evictions.erase(
      std::remove_if(evictions.begin(), evictions.end(),
                     [](const auto& row) { return row.size() > 6 && row[6] == "refused"; }),
      evictions.end());
  ASSERT_GT(evictions.size(), 50u);
  auto dropped = object<CSetOfLines>(scene, names::kDropped);
  ASSERT_TRUE(dropped);
  EXPECT_EQ(dropped->getLineCount(), 2 * evictions.size());

  // The robot at the last pose of the EKF (the last row of trajectory.tum).
  auto robot = object<CSetOfObjects>(scene, names::kRobot);
  ASSERT_TRUE(robot);
  EXPECT_NEAR(robot->getPoseX(), tum.back()[1], kFloat);
  EXPECT_NEAR(robot->getPoseY(), tum.back()[2], kFloat);
  EXPECT_NEAR(robot->getPoseYaw(),  // [deg]
              mrpt::RAD2DEG(mrpt::math::wrapToPi(2 * std::atan2(tum.back()[6], tum.back()[7]))),
              1e-4);

  auto title = object<CText>(scene, names::kTitle);
  ASSERT_TRUE(title);
  // The rawlog, then the counts of steps.csv: dropped (n_dropped) and refused (n_refused).
  const std::size_t n_refused = refused - evictions.size();
  EXPECT_EQ(title->getString(),
            "kf-slam_demo.rawlog: ekf, reducer coverage, cap 20: 20 landmarks "
            "kept, " +
                std::to_string(evictions.size()) + " dropped" +
                (n_refused ? ", " + std::to_string(n_refused) + " refused" : std::string()));
  std::size_t sum_dropped = 0, sum_refused = 0;
  const auto steps = readCsvTable(dir / "steps.csv");
  for (std::size_t k = 0; k < steps.rows.size(); ++k) {
    sum_dropped += std::stoul(steps.at(k, "n_dropped"));
    sum_refused += std::stoul(steps.at(k, "n_refused"));
  }
  EXPECT_EQ(sum_dropped, evictions.size());
  EXPECT_EQ(sum_refused, n_refused);
  EXPECT_TRUE(object<CRenderizable>(scene, names::kGrid));
}

TEST(MapScene, OffWhenAskedAndEveryNStepsAsKfSlam) {
  const auto off = freshDir("map_scene_off");
  auto r = runApp({"run", "-c", kRoot + "/config.ini", "-i", kDemo, "-o", off.string(), "--quiet",
                   "--set", "MappingApplication.save_3d_scene=false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(off / "map.png"));
  EXPECT_FALSE(fs::exists(off / "map.3Dscene"));

  // kf-slam's SAVE_3D_SCENES and SAVE_LOG_FREQUENCY: kf_state_<step>.3Dscene every 100 steps.
  const auto every = freshDir("map_scene_every");
  r = runApp({"run", "-c", kRoot + "/config.ini", "-i", kDemo, "-o", every.string(), "--quiet",
              "--set", "MappingApplication.SAVE_3D_SCENES=true", "--set",
              "MappingApplication.SAVE_LOG_FREQUENCY=100"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::set<std::string> scenes;
  for (const auto& f : fs::directory_iterator(every))
    if (f.path().extension() == ".3Dscene") scenes.insert(f.path().filename().string());
  EXPECT_EQ(scenes, (std::set<std::string>{"kf_state_00000.3Dscene", "kf_state_00100.3Dscene",
                                           "kf_state_00200.3Dscene", "map.3Dscene"}));
  // After step 100 the EKF has 101 poses: 100 segments; the landmarks are those of that step.
  const auto at100 = load(every / "kf_state_00100.3Dscene");
  auto path = object<CSetOfLines>(at100, names::kTrajectory);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->getLineCount(), 100u);
  const auto steps = readCsv(every / "steps.csv");
  auto kept = object<CSetOfObjects>(at100, names::kKept);
  ASSERT_TRUE(kept);
  EXPECT_EQ(std::to_string(kept->size()), steps.at(100).at(2));  // n_landmarks after step 100

  r = runApp({"run", "-c", kRoot + "/config.ini", "-i", kDemo, "-o",
              freshDir("map_scene_bad").string(), "--quiet", "--set",
              "MappingApplication.SAVE_3D_SCENES=true", "--set",
              "MappingApplication.SAVE_LOG_FREQUENCY=0"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("SAVE_LOG_FREQUENCY"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace budget_slam::testing
