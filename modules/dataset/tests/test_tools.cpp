#include <gtest/gtest.h>

#include "TestUtil.h"

using namespace budget_slam::dataset::test;

TEST(Tools, ConvertWritesRawlogGroundTruthAndSidecar) {
  TempDir tmp;
  const std::string dir = datasetsDir() + "/freiburg_slam_course";
  const auto r = runTool(tmp, bin("budget-convert") + " --format freiburg '" + dir + "' -o '" +
                                  tmp.file("f.rawlog") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, tmp.file("f.rawlog") +
                       ": 331 steps, 1211 sightings of 9 landmarks, with "
                       "ground truth\n");
  EXPECT_TRUE(fileExists(tmp.file("f_ground_truth.txt")));
  EXPECT_FALSE(fileExists(tmp.file("f_ground_truth_robot_path.txt")));
  const auto ini = readFile(tmp.file("f.ini"));
  EXPECT_NE(ini.find("[RangeBearingKFSLAM]\nstd_sensor_range   = 0.1  // m, 1 sigma\n"
                     "std_sensor_yaw_deg = 5.72957795  // deg, 1 sigma\n"),
            std::string::npos)
      << ini;
  EXPECT_NE(ini.find("# Made by budget-convert --format freiburg from world.dat and "
                     "sensor_data.dat."),
            std::string::npos);
}

TEST(Tools, ConvertReportsBadInputOnOneLine) {
  TempDir tmp;
  const auto f = writeFile(tmp.file("vp.txt"),
                           "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\n"
                           "LANDMARK 1 5 1 oops 0.1 0 0.1\n");
  auto r = runTool(
      tmp, bin("budget-convert") + " --format isam '" + f + "' -o '" + tmp.file("o.rawlog") + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-convert: " + f + ":2: y is not a number: 'oops'\n");
  EXPECT_FALSE(fileExists(tmp.file("o.rawlog")));
  // Bad command lines (wrong number of inputs, an output that is no .rawlog): exit 2.
  r = runTool(tmp, bin("budget-convert") + " --format isam a b -o '" + tmp.file("o.rawlog") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err,
            "budget-convert: --format isam takes one file (victoria_park.txt), got 2 "
            "input(s); see budget-convert --help\n");
  r = runTool(tmp,
              bin("budget-convert") + " --format isam '" + f + "' -o '" + tmp.file("o.txt") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "budget-convert: output '" + tmp.file("o.txt") +
                       "': the rawlog name must end in .rawlog; see budget-convert --help\n");
  r = runTool(tmp, bin("budget-convert") + " --format csv x -o y.rawlog");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Tools, SimulateIsReproducibleAndChecksItsOptions) {
  TempDir tmp;
  const std::string cmd = bin("budget-simulate") + " --scenario paper-synthetic --seed 5 -o '";
  auto r = runTool(tmp, cmd + tmp.file("a.rawlog") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, tmp.file("a.rawlog") + ": 96 steps of scenario paper-synthetic\n");
  ASSERT_EQ(runTool(tmp, cmd + tmp.file("b.rawlog") + "'").status, 0);
  EXPECT_TRUE(readFile(tmp.file("a.rawlog")) == readFile(tmp.file("b.rawlog")));
  EXPECT_NE(readFile(tmp.file("a.ini"))
                .find("# Made by budget-simulate --scenario "
                      "paper-synthetic --seed 5."),
            std::string::npos);
  r = runTool(tmp, bin("budget-simulate") + " --scenario mars -o x.rawlog");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = runTool(tmp, bin("budget-simulate") + " --scenario rooms -o /nonexistent/x.rawlog");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err,
            "budget-simulate: cannot write '/nonexistent/x.rawlog' (No such file or directory)\n");
}
