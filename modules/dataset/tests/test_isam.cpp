#include <gtest/gtest.h>

#include <set>

#include "TestUtil.h"
#include "budget_slam/dataset/Converters.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;

TEST(IsamConverter, VictoriaParkCounts) {
  const auto d = convertIsam(datasetsDir() + "/victoria_park_gtsam/victoria_park.txt");
  std::size_t odometry = 0, sightings = 0, seeing = 0;
  std::set<LandmarkId> ids;
  for (const auto& s : d.steps) {
    odometry += s.odometry.has_value();
    ASSERT_TRUE(s.scan);
    sightings += s.scan->readings.size();
    seeing += !s.scan->readings.empty();
    for (const auto& r : s.scan->readings) ids.insert(r.id);
  }
  EXPECT_EQ(d.steps.size(), 6968u);  // pose 0 sees nothing: no extra first step
  EXPECT_EQ(odometry, 6968u);
  EXPECT_EQ(ids.size(), 151u);
  EXPECT_EQ(sightings, 3640u);
  EXPECT_EQ(seeing, 3331u);
  EXPECT_TRUE(d.ground_truth.empty());
  // GTSAM's noise: v1 = 0.4 everywhere.
  EXPECT_NEAR(d.noise.std_range, std::sqrt(0.4), 1e-12);
  EXPECT_NEAR(d.noise.std_yaw, 0.2, 1e-12);
  // First line: ODOMETRY 0 1 0.000985144 -3.63222e-10 -1.54136e-06 0.0001 0 0 4e-06 0 4e-06
  EXPECT_DOUBLE_EQ(d.steps[0].odometry->mean.x, 0.000985144);
  EXPECT_DOUBLE_EQ(d.steps[0].odometry->cov(0, 0), 0.0001);
  EXPECT_DOUBLE_EQ(d.steps[0].odometry->cov(2, 2), 4e-6);
  // LANDMARK 4 5 11.5387 -3.2007 from pose 4, reached by the 4th ODOMETRY line.
  ASSERT_EQ(d.steps[3].scan->readings.size(), 1u);
  EXPECT_EQ(d.steps[3].scan->readings[0].id, 5);
  EXPECT_NEAR(d.steps[3].scan->readings[0].range, std::hypot(11.5387, -3.2007), 1e-5);
  EXPECT_NEAR(d.steps[3].scan->readings[0].yaw, std::atan2(-3.2007, 11.5387), 1e-6);
}

TEST(IsamConverter, SmallFileWithStartPoseSightings) {
  TempDir tmp;
  const auto f = writeFile(tmp.file("s.txt"),
                           "# comment\n"
                           "LANDMARK 10 50 3 4 0.09 0 0.09\n"
                           "ODOMETRY 10 11 1 0 0.5 0.01 0 0 0.02 0 0.03\n"
                           "LANDMARK 11 50 0 -2 0.09 0 0.09\n"
                           "LANDMARK 11 51 -1 0 0.09 0 0.09\n"
                           "ODOMETRY 11 12 1 0 0 0.01 0.001 0 0.02 0 0.03\n");
  const auto d = convertIsam(f);
  ASSERT_EQ(d.steps.size(), 3u);
  EXPECT_FALSE(d.steps[0].odometry);  // the start pose's sightings, no motion
  EXPECT_EQ(d.steps[0].action->size(), 0u);
  ASSERT_EQ(d.steps[0].scan->readings.size(), 1u);
  EXPECT_NEAR(d.steps[0].scan->readings[0].range, 5, 1e-6);
  EXPECT_NEAR(d.steps[0].scan->readings[0].yaw, std::atan2(4, 3), 1e-6);
  ASSERT_EQ(d.steps[1].scan->readings.size(), 2u);
  EXPECT_NEAR(d.steps[1].scan->readings[0].yaw, -M_PI / 2, 1e-6);
  EXPECT_NEAR(d.steps[1].scan->readings[1].yaw, M_PI, 1e-6);
  EXPECT_EQ(d.steps[1].odometry->mean.phi, 0.5);
  EXPECT_EQ(d.steps[2].odometry->cov(1, 0), 0.001);
  EXPECT_TRUE(d.steps[2].scan->readings.empty());
  EXPECT_NEAR(d.noise.std_range, 0.3, 1e-12);
  EXPECT_NEAR(d.noise.std_yaw, std::sqrt(0.009), 1e-12);
  EXPECT_NEAR(d.noise.max_range, 5, 1e-6);
  EXPECT_NEAR(d.noise.fov_yaw, 2 * M_PI, 1e-6);
  EXPECT_EQ(d.steps[2].t, 3.0);
}

TEST(IsamConverter, MalformedLinesNameFileAndLine) {
  TempDir tmp;
  const auto f = tmp.file("bad.txt");
  const auto err = [&](const std::string& text) {
    writeFile(f, text);
    return inputErrorOf([&] { convertIsam(f); });
  };
  const std::string odo = "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\n";
  EXPECT_EQ(err(odo + "ODOMETRY 1 2 1 0 0 0.01 0 0 0.01\n"),
            f + ":2: ODOMETRY (i j dx dy dtheta + 6 covariance entries) needs 12 fields, found 10");
  EXPECT_EQ(err(odo + "\nODOMETRY 1 2 1 x 0 0.01 0 0 0.01 0 0.01\n"),
            f + ":3: dy is not a number: 'x'");
  EXPECT_EQ(err(odo + "ODOMETRY 3 4 1 0 0 0.01 0 0 0.01 0 0.01\n"),
            f + ":2: ODOMETRY 3 4 does not start at pose 1, where the previous ODOMETRY ended "
                "(the odometry must form one chain)");
  EXPECT_EQ(err(odo + "ODOMETRY 1 0 1 0 0 0.01 0 0 0.01 0 0.01\n"),
            f + ":2: ODOMETRY 1 0 reaches pose 0 a second time (first on line 1)");
  EXPECT_EQ(err("ODOMETRY 0 1 1 0 0 0.01 0.5 0 0.01 0 0.01\n"),
            f + ":1: covariance is not positive semi-definite");
  EXPECT_EQ(err(odo + "LANDMARK 7 5 1 1 0.1 0 0.1\n"),
            f + ":2: LANDMARK from pose 7, which no ODOMETRY record reaches");
  EXPECT_EQ(err(odo + "LANDMARK 1 5 1 1 0.1 0 0.1\nLANDMARK 1 5 1 2 0.1 0 0.1\n"),
            f + ":3: landmark 5 seen twice from pose 1 (first on line 2)");
  EXPECT_EQ(err(odo + "LANDMARK 1 0 1 1 0.1 0 0.1\n"),
            f + ":2: landmark id 0 is also a pose (line 1)");
  EXPECT_EQ(err(odo + "LANDMARK 1 5 0 0 0.1 0 0.1\n"),
            f + ":2: LANDMARK at zero range has no bearing");
  EXPECT_EQ(err(odo + "LANDMARK 1 5 1 1 0 0 0.1\n"),
            f + ":2: variance v1 must be at least 1e-23, found '0'");
  EXPECT_EQ(err(odo + "POINT 1 2\n"),
            f + ":2: unknown record 'POINT' (expected ODOMETRY or LANDMARK)");
  EXPECT_EQ(err("LANDMARK 1 5 1 1 0.1 0 0.1\n"), f + ": no ODOMETRY record (nothing to convert)");
  EXPECT_EQ(inputErrorOf([&] { convertIsam(tmp.file("none.txt")); }),
            tmp.file("none.txt") + ": cannot open (No such file or directory)");
}
