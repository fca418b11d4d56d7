#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"

using namespace budget_slam;
using namespace budget_slam::report;
namespace fs = std::filesystem;

namespace {
fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("budget_slam_readers_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// The error message of reading `text` as landmarks.csv.
std::string landmarksError(const std::string& text) {
  const auto d = tempDir("bad");
  write(d / "landmarks.csv", text);
  try {
    readLandmarksCsv((d / "landmarks.csv").string(), 100);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
const std::string kHeader =
    "id,x,y,cov_xx,cov_xy,cov_yy,n_obs,obs_mean_x,obs_mean_y,first_step,last_step\n";
}  // namespace

TEST(RunFileReaders, LandmarksRoundTrip) {
  std::vector<LandmarkView> lms(3);
  for (int i = 0; i < 3; ++i) {
    lms[i].id = 10 + i;
    lms[i].mean = Eigen::Vector2d(0.1 * i - 3, 1.0 / 3 + i);
    lms[i].cov << 0.01 + i, 0.002, 0.002, 0.03;
    lms[i].n_obs = 5 * i;
    lms[i].obs_mean = Eigen::Vector2d(i, -i);
    lms[i].first_step = i;
    lms[i].last_step = 7 * i;
  }
  const auto d = tempDir("round");
  writeLandmarksCsv((d / "landmarks.csv").string(), lms);
  const auto back = readLandmarksCsv((d / "landmarks.csv").string(), 100);
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].id, lms[i].id);
    EXPECT_EQ(back[i].mean, lms[i].mean);  // shortest round-trip formatting: exact
    EXPECT_EQ(back[i].cov, lms[i].cov);
    EXPECT_EQ(back[i].n_obs, lms[i].n_obs);
    EXPECT_EQ(back[i].last_step, lms[i].last_step);
  }
  writeLandmarksCsv((d / "empty.csv").string(), {});
  EXPECT_TRUE(readLandmarksCsv((d / "empty.csv").string(), 100).empty());
}

TEST(RunFileReaders, BadLandmarksAreOneLineNamingFileAndLine) {
  const auto d = tempDir("missing");
  try {
    readLandmarksCsv((d / "landmarks.csv").string(), 100);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (d / "landmarks.csv").string() + ": cannot open (no such file)");
  }
  const std::string f = (fs::temp_directory_path() / "budget_slam_readers_bad/landmarks.csv").string();
  EXPECT_EQ(landmarksError(""), f + ":1: empty file (expected the header '" +
                                    kHeader.substr(0, kHeader.size() - 1) + "')");
  EXPECT_EQ(landmarksError("id,x,y\n1,2,3\n"),
            f + ":1: not a budget-slam landmarks.csv header: 'id,x,y'");
  EXPECT_EQ(landmarksError(kHeader + "1,2,3\n"),
            f + ":2: expected 11 cells (" + kHeader.substr(0, kHeader.size() - 1) + "), found 3");
  EXPECT_EQ(landmarksError(kHeader + "1,nan,0,1,0,1,1,0,0,0,0\n"),
            f + ":2: x is not a finite number: 'nan'");
  EXPECT_EQ(landmarksError(kHeader + "-1,0,0,1,0,1,1,0,0,0,0\n"),
            f + ":2: id is not a non-negative integer: '-1'");
  EXPECT_EQ(landmarksError(kHeader + "1,0,0,1,0,1,1,0,0,0,0\n1,0,0,1,0,1,1,0,0,0,0\n"),
            f + ":3: landmark id 1 appears twice");
  EXPECT_EQ(landmarksError(kHeader + "1,0,0,1,2,1,1,0,0,0,0\n"),
            f + ":2: covariance (cov_xx, cov_xy, cov_yy) = (1, 2, 1) is not positive semi-definite");
  std::string many = kHeader;
  for (int i = 0; i < 101; ++i) many += std::to_string(i) + ",0,0,1,0,1,1,0,0,0,0\n";
  EXPECT_EQ(landmarksError(many), f + ":102: more than 100 landmarks");
  EXPECT_EQ(landmarksError(kHeader + std::string(5000, '1') + "\n"),
            f + ":1: line longer than 4096 bytes");
}

TEST(RunFileReaders, TrajectoryRoundTripAndErrors) {
  std::vector<TrajectoryPoint> traj = {{0, 1.5, {1, 2, 0.3}}, {1, 2.5, {-1, 0.5, -3.0}},
                                       {2, 4, {0, 0, 3.1}}};
  const auto d = tempDir("tum");
  writeTrajectoryTum((d / "t.tum").string(), traj);
  const auto back = readTrajectoryTum((d / "t.tum").string(), 10);
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].t, traj[i].t);
    EXPECT_EQ(back[i].pose.x, traj[i].pose.x);
    EXPECT_NEAR(back[i].pose.phi, traj[i].pose.phi, 1e-12);
  }
  write(d / "bad.tum", "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  try {
    readTrajectoryTum((d / "bad.tum").string(), 10);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (d / "bad.tum").string() + ":2: time 1 does not increase");
  }
}
