#include <gtest/gtest.h>

#include <regex>
#include <set>

#include "TestUtil.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/RawlogReader.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;

namespace {

/// The rawlogs tools/make_rawlogs.sh makes, and whether they come with ground truth.
const std::vector<std::pair<std::string, bool>> kMade = {{"victoria_park", false},
                                                         {"mrclam7_robot1", true},
                                                         {"rooms", true},
                                                         {"paper_synthetic", true},
                                                         {"park", true},
                                                         {"corridors", true},
                                                         {"clusters", true},
                                                         {"rooms_revisit", true},
                                                         {"park_revisit", true},
                                                         {"corridors_revisit", true},
                                                         {"clusters_revisit", true},
                                                         {"mrclam7_robot2", true},
                                                         {"mrclam7_robot3", true},
                                                         {"mrclam7_robot4", true},
                                                         {"mrclam7_robot5", true},
                                                         {"victoria_park_from3500", false}};

std::string rawlogsDir() { return sourceDir() + "/rawlogs/"; }

/// Every shipped rawlog: the ones above plus MRPT's kf-slam demo when it is there.
std::vector<std::string> shippedRawlogs() {
  std::vector<std::string> names;
  for (const auto& [name, gt] : kMade) names.push_back(name);
  if (fileExists(rawlogsDir() + "kf-slam_demo.rawlog")) names.push_back("kf-slam_demo");
  return names;
}

}  // namespace

TEST(ShippedRawlogs, MakeRawlogsRebuildsThemByteForByte) {
  TempDir tmp;
  ASSERT_EQ(run("BUDGET_SLAM_BIN='" + std::string(BUDGET_SLAM_BINARY_DIR) + "/bin' '" +
                sourceDir() + "/tools/make_rawlogs.sh' '" + tmp.path() + "' > /dev/null"),
            0);
  for (const auto& [name, has_gt] : kMade) {
    std::vector<std::string> files = {name + ".rawlog", name + ".ini"};
    if (has_gt) {
      files.push_back(name + "_ground_truth.txt");
      files.push_back(name + "_ground_truth_robot_path.txt");
    }
    for (const auto& f : files) {
      ASSERT_TRUE(fileExists(rawlogsDir() + f)) << f << " is not shipped";
      EXPECT_TRUE(readFile(rawlogsDir() + f) == readFile(tmp.file(f)))
          << "rawlogs/" << f << " differs from what tools/make_rawlogs.sh makes";
    }
    EXPECT_EQ(fileExists(rawlogsDir() + name + "_ground_truth.txt"), has_gt) << name;
  }
}

TEST(ShippedRawlogs, CountsAfterConversion) {
  struct Expect {
    std::string name;
    std::size_t steps, odometry, landmarks, sightings;
  };
  // Victoria Park: 6,968 ODOMETRY lines, 151 landmarks, 3,640 LANDMARK lines. MRCLAM7 robot 1:
  // the 2,578 landmark lines of Robot1_Measurement.dat (3,228 minus 650 sightings of robots) at
  // 1,663 distinct times, 15 landmarks.
  const std::vector<Expect> expect = {{"victoria_park", 6968, 6968, 151, 3640},
                                      {"mrclam7_robot1", 1663, 1663, 15, 2578}};
  for (const auto& e : expect) {
    const auto steps = readAllSteps(rawlogsDir() + e.name + ".rawlog");
    std::size_t odometry = 0, sightings = 0;
    std::set<LandmarkId> ids;
    for (const auto& s : steps) {
      odometry += s.odometry.has_value();
      for (const auto& r : s.scan->readings) {
        ++sightings;
        ids.insert(r.id);
      }
    }
    EXPECT_EQ(steps.size(), e.steps) << e.name;
    EXPECT_EQ(odometry, e.odometry) << e.name;
    EXPECT_EQ(ids.size(), e.landmarks) << e.name;
    EXPECT_EQ(sightings, e.sightings) << e.name;
  }
  const auto gt = loadGroundTruth(rawlogsDir() + "mrclam7_robot1.rawlog");
  EXPECT_EQ(gt.landmarks.size(), 15u);
  EXPECT_EQ(gt.path.size(), 1664u);
}

// The second traversals share their first traversal's world: the same landmarks, ids and frame
// (the first traversal's start pose is the origin), another path; Victoria Park's second part is
// the whole file's steps from 3500 on, times and readings unchanged.
TEST(ShippedRawlogs, SecondTraversalsShareTheWorldOfTheFirst) {
  for (const auto& [first, second] :
       std::vector<std::pair<std::string, std::string>>{{"rooms", "rooms_revisit"},
                                                        {"park", "park_revisit"},
                                                        {"corridors", "corridors_revisit"},
                                                        {"clusters", "clusters_revisit"},
                                                        {"mrclam7_robot1", "mrclam7_robot2"},
                                                        {"mrclam7_robot1", "mrclam7_robot3"},
                                                        {"mrclam7_robot1", "mrclam7_robot4"},
                                                        {"mrclam7_robot1", "mrclam7_robot5"}}) {
    const auto a = loadGroundTruth(rawlogsDir() + first + ".rawlog");
    const auto b = loadGroundTruth(rawlogsDir() + second + ".rawlog");
    EXPECT_EQ(a.landmarks.size(), b.landmarks.size()) << second;
    for (const auto& [id, p] : a.landmarks) {
      ASSERT_TRUE(b.landmarks.count(id)) << second << " lacks landmark " << id;
      EXPECT_LT((b.landmarks.at(id) - p).norm(), 1e-6) << second << " landmark " << id;
    }
    // Another start: not the first traversal's origin.
    EXPECT_GT(std::hypot(b.path.front().x, b.path.front().y), 0.3) << second;
    // Every reading of a landmark the first traversal's ground truth holds.
    for (const auto& s : readAllSteps(rawlogsDir() + second + ".rawlog"))
      for (const auto& r : s.scan->readings) EXPECT_TRUE(a.landmarks.count(r.id)) << second;
  }
  const auto whole = readAllSteps(rawlogsDir() + "victoria_park.rawlog");
  const auto rest = readAllSteps(rawlogsDir() + "victoria_park_from3500.rawlog");
  ASSERT_EQ(rest.size(), whole.size() - 3500);
  for (std::size_t k = 0; k < rest.size(); k += 97) {
    EXPECT_EQ(rest[k].t, whole[3500 + k].t);
    ASSERT_EQ(rest[k].scan->readings.size(), whole[3500 + k].scan->readings.size());
    for (std::size_t r = 0; r < rest[k].scan->readings.size(); ++r)
      EXPECT_EQ(rest[k].scan->readings[r].id, whole[3500 + k].scan->readings[r].id);
    EXPECT_EQ(rest[k].odometry->mean.x, whole[3500 + k].odometry->mean.x);
  }
}

TEST(ShippedRawlogs, RawlogEditReadsEveryOne) {
  TempDir tmp;
  for (const auto& name : shippedRawlogs()) {
    const std::string out = tmp.file(name + ".info");
    EXPECT_EQ(
        run("rawlog-edit --info -i '" + rawlogsDir() + name + ".rawlog' > '" + out + "' 2>&1"), 0)
        << name;
    EXPECT_NE(readFile(out).find("Actions/SensoryFrame format       : Yes"), std::string::npos)
        << name << ": " << readFile(out);
  }
}

TEST(ShippedRawlogs, KfSlamRunsOnEveryOne) {
  // MRPT's own kf-slam, headless, with the sidecar's sensor noise. Where there is landmark
  // ground truth, its mean landmark error must stay under a bound that catches a broken rawlog
  // (a wrong frame, sign or unit gives errors of metres) with room for each dataset's drift
  // (measured: rooms 0.05 m, paper_synthetic 0.21 m, park 0.45 m, mrclam7_robot1 3.0 m). MRCLAM's
  // velocity-command odometry turns the whole map by tens of degrees before a landmark is seen
  // twice, which an EKF cannot undo (compare it after alignment).
  const std::map<std::string, double> bound = {{"rooms", 0.2},
                                               {"paper_synthetic", 0.6},
                                               {"park", 1.0},
                                               {"mrclam7_robot1", 4.0},
                                               {"kf-slam_demo", 0.5}};
  for (const auto& name : shippedRawlogs()) {
    TempDir tmp;
    const std::string rawlog = rawlogsDir() + name + ".rawlog";
    std::string ini =
        "[MappingApplication]\n"
        "kf_implementation = CRangeBearingKFSLAM2D\n"
        "rawlog_file = " +
        rawlog +
        "\n"
        "logOutput_dir = " +
        tmp.file("out") +
        "\n"
        "SHOW_3D_LIVE = false\nSAVE_3D_SCENES = false\nSAVE_MAP_REPRESENTATIONS = false\n"
        "SAVE_LOG_FREQUENCY = 1000000\n";
    if (fileExists(groundTruthLandmarksPathFor(rawlog)))
      ini += "ground_truth_file = " + groundTruthLandmarksPathFor(rawlog) + "\n";
    const std::string sidecar = rawlogsDir() + name + ".ini";
    ini += fileExists(sidecar) ? readFile(sidecar)
                               : "[RangeBearingKFSLAM]\nstd_sensor_range = 0.01\n"
                                 "std_sensor_yaw_deg = 0.1\n";
    writeFile(tmp.file("kf.ini"), ini);
    const std::string log = tmp.file("kf.log");
    ASSERT_EQ(run("kf-slam '" + tmp.file("kf.ini") + "' > '" + log + "' 2>&1"), 0) << name;
    const std::string text = readFile(log);
    EXPECT_NE(text.find("KF-SLAM finished"), std::string::npos) << name;
    EXPECT_EQ(text.find("nan"), std::string::npos) << name << ": the filter diverged";
    std::smatch m;
    if (bound.count(name)) {
      ASSERT_TRUE(std::regex_search(text, m, std::regex("Mean Error: ([0-9.]+) meters"))) << name;
      EXPECT_LT(std::stod(m[1]), bound.at(name)) << name;
    }
  }
}
