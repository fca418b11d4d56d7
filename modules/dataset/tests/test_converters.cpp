#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <set>

#include "TestUtil.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Converters.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;

namespace {

struct Counts {
  std::size_t steps = 0, odometry = 0, sightings = 0;
  std::set<LandmarkId> ids;
};

Counts count(const ConvertedDataset& d) {
  Counts c;
  c.steps = d.steps.size();
  for (const auto& s : d.steps) {
    c.odometry += s.odometry.has_value();
    if (s.scan) {
      c.sightings += s.scan->readings.size();
      for (const auto& r : s.scan->readings) c.ids.insert(r.id);
    }
  }
  return c;
}

}  // namespace

TEST(G2oConverter, SampleCounts) {
  const auto d = convertG2o(datasetsDir() + "/g2o_sample/simulation-pose-landmark.g2o");
  const auto c = count(d);
  // 41 poses: the start pose plus one per EDGE_SE2 (the start pose sees nothing).
  EXPECT_EQ(c.odometry + 1, 41u);
  EXPECT_EQ(c.steps, 40u);
  EXPECT_EQ(c.ids.size(), 36u);
  EXPECT_EQ(c.sightings, 257u);
  // Information 100 in x and y: std 0.1 m in range; bearing 0.1 m / range.
  EXPECT_NEAR(d.noise.std_range, 0.1, 1e-9);
  // EDGE_SE2 100 101 0.112639 0.023666 -1.570660, information diag(100, 100, 1000).
  EXPECT_DOUBLE_EQ(d.steps[0].odometry->mean.x, 0.112639);
  EXPECT_NEAR(d.steps[0].odometry->cov(2, 2), 1e-3, 1e-15);
}

TEST(G2oConverter, SmallFileAndErrors) {
  TempDir tmp;
  const auto f = tmp.file("g.g2o");
  writeFile(f,
            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_XY 7 3 4\nFIX 0\n"
            "EDGE_SE2 0 1 1 0 0 100 0 0 100 0 400\n"
            "EDGE_SE2_XY 1 7 0 2 25 0 25\n");
  const auto d = convertG2o(f);
  ASSERT_EQ(d.steps.size(), 1u);
  EXPECT_NEAR(d.steps[0].odometry->cov(2, 2), 1.0 / 400, 1e-15);
  ASSERT_EQ(d.steps[0].scan->readings.size(), 1u);
  EXPECT_NEAR(d.steps[0].scan->readings[0].yaw, M_PI / 2, 1e-6);
  EXPECT_NEAR(d.noise.std_range, 0.2, 1e-12);
  EXPECT_NEAR(d.noise.std_yaw, 0.1, 1e-12);  // 0.2 m at 2 m

  const auto err = [&](const std::string& text) {
    writeFile(f, text);
    return inputErrorOf([&] { convertG2o(f); });
  };
  const std::string v = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_XY 7 3 4\n";
  EXPECT_EQ(err(v + "EDGE_SE2 0 1 1 0 0 100 0 0 -100 0 400\n"),
            f + ":4: information matrix is not positive definite");
  EXPECT_EQ(err(v + "EDGE_SE2 0 1 1 0 0 100 0 0 100 0 400\nEDGE_SE2_XY 1 8 0 2 25 0 25\n"),
            f + ":5: vertex 8 is not declared by a VERTEX_XY line");
  EXPECT_EQ(
      err(v + "EDGE_SE2 0 1 1 0 0 100 0 0 100 0\n"),
      f + ":4: EDGE_SE2 (i j dx dy dtheta + 6 information entries) needs 12 fields, found 11");
  EXPECT_EQ(err(v + "VERTEX_SE3:QUAT 2 0 0 0 0 0 0 1\n"),
            f + ":4: unknown record 'VERTEX_SE3:QUAT' (expected VERTEX_SE2, VERTEX_XY, EDGE_SE2, "
                "EDGE_SE2_XY or FIX)");
  EXPECT_EQ(err(v + "VERTEX_XY 1 0 0\n"), f + ":4: vertex 1 is declared twice (first on line 2)");
  EXPECT_EQ(err(v + "EDGE_SE2 0 1 1 0 0 100 0 0 100 0 400\nEDGE_SE2 0 1 1 0 0 100 0 0 100 0 400\n"),
            f + ":5: EDGE_SE2 0 1 does not start at pose 1, where the previous EDGE_SE2 ended (the "
                "odometry must form one chain)");
}

TEST(FreiburgConverter, CourseDataCounts) {
  const std::string dir = datasetsDir() + "/freiburg_slam_course/";
  const auto d = convertFreiburg(dir + "world.dat", dir + "sensor_data.dat");
  const auto c = count(d);
  EXPECT_EQ(c.steps, 331u);
  EXPECT_EQ(c.odometry, 331u);
  // 1,212 SENSOR lines, one with a negative range (-0.035 m) left out.
  EXPECT_EQ(c.sightings, 1211u);
  EXPECT_EQ(d.notes.back(), "SENSOR readings with a negative range left out: 1.");
  EXPECT_EQ(d.ground_truth.landmarks.size(), 9u);
  EXPECT_EQ(d.ground_truth.landmarks.at(2), Eigen::Vector2d(0, 4));
  EXPECT_TRUE(d.ground_truth.path.empty());
  EXPECT_NEAR(d.noise.std_range, 0.1, 1e-12);
  // ODOMETRY 0.100692392654 0.100072845247 0.000171392857486
  EXPECT_NEAR(d.steps[0].odometry->mean.x, 0.100072845247 * std::cos(0.100692392654), 1e-15);
  EXPECT_NEAR(d.steps[0].odometry->mean.phi, 0.100692392654 + 0.000171392857486, 1e-15);
}

TEST(FreiburgConverter, MalformedLines) {
  TempDir tmp;
  const auto w = writeFile(tmp.file("world.dat"), "1 2 1\n2 0 4\n");
  const auto s = tmp.file("sensor_data.dat");
  const auto err = [&](const std::string& text) {
    writeFile(s, text);
    return inputErrorOf([&] { convertFreiburg(w, s); });
  };
  EXPECT_EQ(err("ODOMETRY 0.1 0.1 0\nSENSOR 1 2\n"),
            s + ":2: SENSOR (id range bearing) needs 4 fields, found 3");
  EXPECT_EQ(err("ODOMETRY 0.1 0.1 0\nSENSOR 1 2 0.1\nSENSOR 1 3 0.1\n"),
            s + ":3: landmark 1 seen twice in one step (first on line 2)");
  EXPECT_EQ(err("ODOMETRY 0.1 zero 0\n"), s + ":1: t is not a number: 'zero'");
  EXPECT_EQ(err("ODOMETRY 0.1 0.1 0\nSENSOR 1 nan 0.1\n"),
            s + ":2: range is not a finite number: 'nan'");
  EXPECT_EQ(err("MOVE 1\n"), s + ":1: unknown record 'MOVE' (expected ODOMETRY or SENSOR)");
  writeFile(w, "1 2 1\n1 0 4\n");
  EXPECT_EQ(err("ODOMETRY 0.1 0.1 0\n"), w + ":2: landmark id 1 appears twice (first on line 1)");
}

TEST(UtiasConverter, Mrclam7Robot1) {
  const auto d = convertUtias(datasetsDir() + "/utias_mrclam/MRCLAM_Dataset7", 1);
  const auto c = count(d);
  // Every landmark sighting of Robot1_Measurement.dat (3,228 lines, 650 of robots).
  EXPECT_EQ(c.sightings, 2578u);
  EXPECT_EQ(c.odometry, c.steps);
  EXPECT_EQ(d.ground_truth.path.size(), c.steps + 1);
  EXPECT_EQ(d.ground_truth.landmarks.size(), 15u);
  EXPECT_LE(c.ids.size(), 15u);
  for (const auto id : c.ids) EXPECT_TRUE(id >= 6 && id <= 20) << id;
  // Fitted noise in a plausible band for this sensor (monocular camera, barcodes).
  EXPECT_GT(d.noise.std_range, 0.01);
  EXPECT_LT(d.noise.std_range, 0.5);
  EXPECT_GT(d.noise.std_yaw, 0.001);
  EXPECT_LT(d.noise.std_yaw, 0.2);
}

namespace {

/// A two-step MRCLAM-like folder.
std::string writeTinyUtias(const TempDir& tmp) {
  writeFile(tmp.file("Barcodes.dat"), "# subject barcode\n1 5\n6 63\n7 81\n");
  writeFile(tmp.file("Landmark_Groundtruth.dat"), "6 1 0 0 0\n7 3 1 0 0\n");
  writeFile(tmp.file("Robot1_Odometry.dat"), "100 1 0\n102 0 0\n");
  writeFile(tmp.file("Robot1_Groundtruth.dat"),
            "100 1 1 1.5707963267948966\n102 1 3 1.5707963267948966\n");
  writeFile(tmp.file("Robot1_Measurement.dat"),
            "100.5 63 0.5 0\n100.5 5 1 0\n101 81 2 0.1\n101.5 99 1 0\n");
  return tmp.path();
}

}  // namespace

TEST(UtiasConverter, TinyFolder) {
  TempDir tmp;
  const auto d = convertUtias(writeTinyUtias(tmp), 1);
  ASSERT_EQ(d.steps.size(), 2u);
  // The first step (t = 100.5) defines the start pose: zero motion; then 0.5 s at 1 m/s.
  EXPECT_EQ(d.steps[0].odometry->mean.x, 0);
  EXPECT_NEAR(d.steps[1].odometry->mean.x, 0.5, 1e-12);
  EXPECT_NEAR(d.steps[1].odometry->mean.y, 0, 1e-12);
  EXPECT_NEAR(d.steps[1].t, 101, 1e-6);
  ASSERT_EQ(d.steps[0].scan->readings.size(), 1u);  // the robot (barcode 5) is left out
  EXPECT_EQ(d.steps[0].scan->readings[0].id, 6);
  EXPECT_EQ(d.steps[1].scan->readings[0].id, 7);
  // Ground truth in the start frame: Vicon (1, 1.5, 90 deg) at t = 100.5, driving along world +y.
  ASSERT_EQ(d.ground_truth.path.size(), 3u);
  EXPECT_NEAR(d.ground_truth.path[1].x, 0.0, 1e-12);
  EXPECT_NEAR(d.ground_truth.path[2].x, 0.5, 1e-12);
  EXPECT_NEAR(d.ground_truth.path[2].y, 0.0, 1e-12);
  // World (3, 1): 2 m to the right of and 0.5 m behind the start pose.
  EXPECT_NEAR(d.ground_truth.landmarks.at(7).x(), -0.5, 1e-12);
  EXPECT_NEAR(d.ground_truth.landmarks.at(7).y(), -2.0, 1e-12);
}

// With --frame-robot, a robot's ground truth goes into another robot's start frame: robot 2 of
// the tiny folder starts at Vicon (3, 1, 0), robot 1 at (1, 1.5, 90 deg).
TEST(UtiasConverter, GroundTruthInAnotherRobotsFrame) {
  TempDir tmp;
  const auto dir = writeTinyUtias(tmp);
  writeFile(tmp.file("Robot2_Odometry.dat"), "100 1 0\n102 1 0\n");
  writeFile(tmp.file("Robot2_Groundtruth.dat"), "100 2.5 1 0\n102 4.5 1 0\n");
  writeFile(tmp.file("Robot2_Measurement.dat"), "100.5 81 0.5 0\n101 63 2 3.0\n");
  const auto own = convertUtias(dir, 2);
  const auto shared = convertUtias(dir, 2, 1);
  ASSERT_EQ(shared.steps.size(), own.steps.size());
  for (std::size_t k = 0; k < own.steps.size(); ++k)  // the data itself is the same
    EXPECT_EQ(shared.steps[k].odometry->mean.x, own.steps[k].odometry->mean.x);
  EXPECT_NEAR(own.ground_truth.path[0].x, 0, 1e-12);
  // Robot 2's start (3, 1, 0) seen from robot 1's start (1, 1.5, 90 deg): 0.5 m behind, 2 m to
  // the right, heading -90 deg.
  ASSERT_EQ(shared.ground_truth.path.size(), 3u);
  EXPECT_NEAR(shared.ground_truth.path[0].x, -0.5, 1e-12);
  EXPECT_NEAR(shared.ground_truth.path[0].y, -2.0, 1e-12);
  EXPECT_NEAR(shared.ground_truth.path[0].phi, -M_PI / 2, 1e-12);
  // Landmarks as robot 1's own conversion has them.
  const auto r1 = convertUtias(dir, 1);
  for (const auto& [id, p] : r1.ground_truth.landmarks)
    EXPECT_LT((shared.ground_truth.landmarks.at(id) - p).norm(), 1e-12) << id;
  // Its own number as frame robot changes nothing.
  EXPECT_EQ(convertUtias(dir, 1, 1).ground_truth.path[2].x, r1.ground_truth.path[2].x);
  EXPECT_EQ(inputErrorOf([&] { convertUtias(dir, 2, 7); }),
            "UTIAS frame robot number must be 1 to 5, found 7");
}

TEST(SelectSteps, KeepsTimesReadingsAndTheMatchingGroundTruthRows) {
  TempDir tmp;
  const auto d = convertUtias(writeTinyUtias(tmp), 1);
  const auto cut = selectSteps(d, 1, 99);
  ASSERT_EQ(cut.steps.size(), 1u);
  EXPECT_EQ(cut.steps[0].index, 0u);
  EXPECT_EQ(cut.steps[0].t, d.steps[1].t);
  EXPECT_EQ(cut.steps[0].scan->readings[0].id, 7);
  ASSERT_EQ(cut.ground_truth.path.size(), 2u);  // the pose before step 1, and step 1's
  EXPECT_EQ(cut.ground_truth.path[0].x, d.ground_truth.path[1].x);
  EXPECT_EQ(cut.ground_truth.path[1].x, d.ground_truth.path[2].x);
  EXPECT_EQ(cut.ground_truth.landmarks.size(), d.ground_truth.landmarks.size());
  EXPECT_NE(cut.notes.back().find("--steps 1:2"), std::string::npos) << cut.notes.back();
  try {
    selectSteps(d, 2, 5);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "--steps 2:2: no step of the 2 selected");
  }
}

TEST(UtiasConverter, MalformedInputs) {
  TempDir tmp;
  const auto dir = writeTinyUtias(tmp);
  writeFile(tmp.file("Robot1_Measurement.dat"), "100.5 63 0.5 0\n# c\n101 81 2\n");
  EXPECT_EQ(inputErrorOf([&] { convertUtias(dir, 1); }),
            tmp.file("Robot1_Measurement.dat") +
                ":3: measurement record (time barcode range bearing) needs 4 fields, found 3");
  writeFile(tmp.file("Robot1_Measurement.dat"), "101 63 0.5 0\n100 81 2 0\n");
  EXPECT_EQ(
      inputErrorOf([&] { convertUtias(dir, 1); }),
      tmp.file("Robot1_Measurement.dat") + ":2: time 100 is earlier than the previous record's");
  EXPECT_EQ(inputErrorOf([&] { convertUtias(dir, 2); }),
            "UTIAS folder '" + dir +
                "': missing Robot2_Odometry (or Odometry), Robot2_Groundtruth (or Groundtruth), "
                "Robot2_Measurement (or Measurement) (each as .dat, .dat.gz or .csv; "
                "docs/DATASETS.md shows the layout)");
  EXPECT_EQ(inputErrorOf([&] { convertUtias(dir, 6); }),
            "UTIAS robot number must be 1 to 5, found 6");
}

// Issue 35: UTIAS data in the CSV form other projects ship (Barcodes.csv, Landmark_Groundtruth.csv,
// and one robot's Odometry.csv, Groundtruth.csv, Measurement.csv, each with a header line)
// converts exactly as the same records in MRCLAM's .dat form; a folder missing files names every
// one of them at once.
TEST(UtiasConverter, CsvFormConvertsAsTheDatForm) {
  TempDir dat, csv;
  const auto expected = convertUtias(writeTinyUtias(dat), 1);
  writeFile(csv.file("Barcodes.csv"), "Subject,Barcode\n1,5\n6,63\n7,81\n");
  writeFile(csv.file("Landmark_Groundtruth.csv"), "Subject,X,Y,Xstd,Ystd\n6,1,0,0,0\n7,3,1,0,0\n");
  writeFile(csv.file("Odometry.csv"), "Time,Forward,Angular\n100,1,0\n102,0,0\n");
  writeFile(csv.file("Groundtruth.csv"),
            "Time,X,Y,Orientation\n100, 1, 1, 1.5707963267948966\n102, 3 ,1.5707963267948966\n");
  // (the line above has a field too few: fixed below, after its error is checked)
  writeFile(
      csv.file("Measurement.csv"),
      "Time,Subject,Range,Bearing\n100.5,63,0.5,0\n100.5,5,1,0\n101,81,2,0.1\n101.5,99,1,0\n");
  EXPECT_EQ(inputErrorOf([&] { convertUtias(csv.path(), 1); }),
            csv.file("Groundtruth.csv") +
                ":3: ground-truth record (time x y theta) needs 4 fields, found 3");
  writeFile(csv.file("Groundtruth.csv"),
            "Time,X,Y,Orientation\n100, 1, 1, 1.5707963267948966\n102,1,3,1.5707963267948966\n");
  const auto d = convertUtias(csv.path(), 1);
  ASSERT_EQ(d.steps.size(), expected.steps.size());
  for (std::size_t k = 0; k < d.steps.size(); ++k) {
    EXPECT_EQ(d.steps[k].t, expected.steps[k].t);
    EXPECT_EQ(d.steps[k].odometry->mean.x, expected.steps[k].odometry->mean.x);
    ASSERT_EQ(d.steps[k].scan->readings.size(), expected.steps[k].scan->readings.size());
    EXPECT_EQ(d.steps[k].scan->readings[0].id, expected.steps[k].scan->readings[0].id);
  }
  ASSERT_EQ(d.ground_truth.path.size(), expected.ground_truth.path.size());
  EXPECT_EQ(d.ground_truth.path.back().x, expected.ground_truth.path.back().x);
  ASSERT_EQ(d.ground_truth.landmarks.size(), expected.ground_truth.landmarks.size());
  for (const auto& [id, p] : expected.ground_truth.landmarks)
    EXPECT_EQ((d.ground_truth.landmarks.at(id) - p).norm(), 0.0) << id;
  EXPECT_EQ(d.noise.std_range, expected.noise.std_range);
  // An empty field is an error naming it, not a shifted column.
  writeFile(csv.file("Odometry.csv"), "Time,Forward,Angular\n100,,0\n");
  EXPECT_EQ(inputErrorOf([&] { convertUtias(csv.path(), 1); }),
            csv.file("Odometry.csv") + ":2: field 2 is empty");
  // Every missing file at once, whichever form the others are in.
  std::remove(csv.file("Barcodes.csv").c_str());
  std::remove(csv.file("Measurement.csv").c_str());
  EXPECT_EQ(inputErrorOf([&] { convertUtias(csv.path(), 1); }),
            "UTIAS folder '" + csv.path() +
                "': missing Barcodes, Robot1_Measurement (or Measurement) (each as .dat, .dat.gz "
                "or .csv; docs/DATASETS.md shows the layout)");
}
