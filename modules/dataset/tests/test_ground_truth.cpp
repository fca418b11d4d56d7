#include <gtest/gtest.h>

#include "TestUtil.h"
#include "budget_slam/dataset/GroundTruth.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;

TEST(GroundTruth, NamesFollowSimulLandmarks) {
  EXPECT_EQ(groundTruthLandmarksPathFor("a/b.rawlog"), "a/b_ground_truth.txt");
  EXPECT_EQ(groundTruthRobotPathFor("a/b.rawlog"), "a/b_ground_truth_robot_path.txt");
  EXPECT_EQ(groundTruthLandmarksPathFor("x.y/b"), "x.y/b_ground_truth.txt");
}

TEST(GroundTruth, LoadsMrptDemoFiles) {
  const std::string dir = sourceDir() + "/rawlogs/";  // copies of MRPT's kf-slam demo files
  const auto gt = loadGroundTruth(dir + "kf-slam_demo.rawlog");
  ASSERT_EQ(gt.landmarks.size(), 70u);
  EXPECT_DOUBLE_EQ(gt.landmarks.at(1).x(), 0.578229);
  EXPECT_DOUBLE_EQ(gt.landmarks.at(70).y(), 1.829709);
  ASSERT_EQ(gt.path.size(), 250u);
  EXPECT_NEAR(gt.path.back().x, 8.4000009294592317, 1e-15);
  EXPECT_NEAR(gt.path.back().phi, 1.1780974527252748, 1e-15);
  EXPECT_EQ(gt.path_file, dir + "kf-slam_demo_ground_truth_robot_path.txt");
}

TEST(GroundTruth, WritesMrptLayoutByteForByte) {
  TempDir tmp;
  // The first rows of MRPT's own kf-slam demo files, reproduced.
  saveGroundTruthLandmarks(tmp.file("l.txt"),
                           {{1, {0.578229, 7.694330}}, {2, {7.054158, 0.402772}}});
  EXPECT_EQ(readFile(tmp.file("l.txt")),
            "  0.578229   7.694330   0.000000    5    0   0.000000 1 \n"
            "  7.054158   0.402772   0.000000    5    0   0.000000 2 \n");
  saveGroundTruthPath(tmp.file("p.txt"), {{0, 0, 0}, {0.2000000029802322, -0.0, 1.5}});
  EXPECT_EQ(readFile(tmp.file("p.txt")),
            "% Columns are: x(m) y(m) z(m) yaw(rad) pitch(rad) roll(rad)\n"
            "% File generated with budget-slam\n"
            "\n"
            "%------------------------------------\n"
            "0.0000000000000000 0.0000000000000000 0.0000000000000000 0.0000000000000000 "
            "0.0000000000000000 0.0000000000000000\n"
            "0.2000000029802322 0.0000000000000000 0.0000000000000000 1.5000000000000000 "
            "0.0000000000000000 0.0000000000000000\n");
}

TEST(GroundTruth, SaveLoadRoundTrip) {
  TempDir tmp;
  const std::string rawlog = tmp.file("run.rawlog");
  const std::map<LandmarkId, Eigen::Vector2d> lms = {{3, {-1.25, 2.5}}, {17, {100.5, -0.125}}};
  const std::vector<Pose2> path = {{0, 0, 0}, {1.0 / 3, -2.0 / 3, -3.0}};
  saveGroundTruthLandmarks(groundTruthLandmarksPathFor(rawlog), lms);
  saveGroundTruthPath(groundTruthRobotPathFor(rawlog), path);
  const auto gt = loadGroundTruth(rawlog);
  ASSERT_EQ(gt.landmarks.size(), 2u);
  EXPECT_EQ(gt.landmarks.at(17), Eigen::Vector2d(100.5, -0.125));
  ASSERT_EQ(gt.path.size(), 2u);
  EXPECT_NEAR(gt.path[1].x, 1.0 / 3, 1e-15);
  EXPECT_NEAR(gt.path[1].y, -2.0 / 3, 1e-15);
  EXPECT_NEAR(gt.path[1].phi, -3.0, 1e-15);
}

TEST(GroundTruth, AbsentFilesGiveEmptyGroundTruth) {
  TempDir tmp;
  const auto gt = loadGroundTruth(tmp.file("none.rawlog"));
  EXPECT_TRUE(gt.empty());
  EXPECT_EQ(gt.landmarks_file, "");
}

TEST(GroundTruth, ThreeColumnPathAccepted) {
  TempDir tmp;
  const auto f = writeFile(tmp.file("p.txt"), "# x y yaw\n1 2 0.5\n\n3 4 -0.5\n");
  const auto gt = loadGroundTruth(tmp.file("r.rawlog"), "", f);
  ASSERT_EQ(gt.path.size(), 2u);
  EXPECT_EQ(gt.path[1].y, 4);
  EXPECT_EQ(gt.path[1].phi, -0.5);
}

TEST(GroundTruth, MalformedFilesNameFileAndLine) {
  TempDir tmp;
  const auto lm = tmp.file("lm.txt");
  const auto r = tmp.file("r.rawlog");
  writeFile(lm, "1 2 0 5 0 0 1\n1 abc 0 5 0 0 2\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, lm); }), lm + ":2: y is not a number: 'abc'");
  writeFile(lm, "1 2 0 5 0 0 1\n% comment\n3 4 0 5 0 0 1\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, lm); }),
            lm + ":3: landmark id 1 appears twice (first on line 1)");
  writeFile(lm, "1 2 0\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, lm); }),
            lm + ":1: landmark row (x y z type seen time id) needs at least 7 fields, found 3");
  writeFile(lm, "1 2 0 5 0 0 1.5\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, lm); }),
            lm + ":1: id is not a non-negative integer: '1.5'");
  const auto p = writeFile(tmp.file("p.txt"), "0 0 0 0 0 0\n1 2 3 4\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, "", p); }),
            p + ":2: robot path row needs 6 fields (x y z yaw pitch roll) or 3 (x y yaw), found 4");
  writeFile(p, "0 0 0 nan 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, "", p); }),
            p + ":1: yaw is not a finite number: 'nan'");
  EXPECT_EQ(inputErrorOf([&] { loadGroundTruth(r, tmp.file("missing.txt")); }),
            tmp.file("missing.txt") + ": cannot open (No such file or directory)");
}
