#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>

#include "budget_slam/report/Pictures.h"

using namespace budget_slam;
using namespace budget_slam::report;
namespace fs = std::filesystem;

namespace {
/// Pixels of exactly this BGR colour.
int count(const cv::Mat& img, cv::Vec3b c) {
  int n = 0;
  for (int r = 0; r < img.rows; ++r)
    for (int k = 0; k < img.cols; ++k) n += img.at<cv::Vec3b>(r, k) == c;
  return n;
}
const cv::Vec3b kRed(30, 30, 220), kGreen(40, 150, 40), kBlue(200, 80, 20);
}  // namespace

TEST(Pictures, MapShowsTrajectoryKeptAndDroppedLandmarks) {
  const auto dir = fs::temp_directory_path() / "budget_slam_pictures";
  fs::create_directories(dir);
  MapContent c;
  c.title = "test map";
  for (int k = 0; k <= 20; ++k) c.trajectory.push_back({0.5 * k, std::sin(0.3 * k), 0});
  LandmarkView l;
  l.mean = {3, 2};
  l.cov << 0.04, 0.01, 0.01, 0.09;
  c.kept = {l};
  const std::string plain = (dir / "plain.png").string();
  writeMapPng(plain, c, 600, 500);
  const cv::Mat a = cv::imread(plain);
  ASSERT_EQ(a.cols, 600);
  ASSERT_GE(a.rows, 400);
  ASSERT_LE(a.rows, 500);
  EXPECT_GT(count(a, kBlue), 100);  // trajectory drawn 2 px wide
  EXPECT_GT(count(a, kGreen), 10);  // landmark dot and ellipse
  const int red_without = count(a, kRed);

  c.dropped = {{1, -2}, {8, 3}};
  const std::string with = (dir / "dropped.png").string();
  writeMapPng(with, c, 600, 500);
  EXPECT_GT(count(cv::imread(with), kRed), red_without + 10);
}

TEST(Pictures, MapColoursThePathByLandmarksInView) {
  const auto dir = fs::temp_directory_path() / "budget_slam_pictures";
  fs::create_directories(dir);
  MapContent c;
  for (int k = 0; k <= 20; ++k) c.trajectory.push_back({0.5 * k, 0, 0});
  const cv::Vec3b path_red(0, 0, 235), orange(0, 150, 255);
  c.trajectory_landmarks.assign(21, 5);  // all >= 2k: blue
  const std::string blue = (dir / "blue.png").string();
  writeMapPng(blue, c, 600, 500);
  const int red_in_legend = count(cv::imread(blue), path_red);
  for (int k = 11; k <= 20; ++k) c.trajectory_landmarks[k] = k < 16 ? 1 : 3;
  const std::string mixed = (dir / "mixed.png").string();
  writeMapPng(mixed, c, 600, 500);
  const cv::Mat img = cv::imread(mixed);
  EXPECT_GT(count(img, path_red), red_in_legend + 50);  // five segments below k
  EXPECT_GT(count(img, orange), 50);
  EXPECT_GT(count(img, kBlue), 50);
}

TEST(Pictures, ChartDrawsEverySeriesAndSkipsNan) {
  const auto dir = fs::temp_directory_path() / "budget_slam_pictures";
  fs::create_directories(dir);
  ChartPanel p{"landmarks", "step", "count", {}, false};
  p.series.push_back({"a", {0, 1, 2, 3}, {1, 2, NAN, 4}});
  p.series.push_back({"b", {0, 1, 2, 3}, {4, 3, 2, 1}});
  const std::string path = (dir / "chart.png").string();
  writeChartPng(path, {p, p}, 800, 300);
  const cv::Mat img = cv::imread(path);
  EXPECT_EQ(img.cols, 800);
  EXPECT_EQ(img.rows, 600);
  EXPECT_GT(count(img, cv::Vec3b(180, 119, 31)), 50);  // series a
  EXPECT_GT(count(img, cv::Vec3b(14, 127, 255)), 50);  // series b
}

TEST(Pictures, ChartKeepsOneColourARunAcrossPanels) {
  // compare without ground truth: the upper panel has every run, the lower one no reference
  // (it shows the difference to the reference). mi must keep its colour in both panels.
  const auto dir = fs::temp_directory_path() / "budget_slam_pictures";
  fs::create_directories(dir);
  ChartPanel count_panel{"landmarks", "step", "landmarks", {}, false};
  ChartPanel error_panel{"difference to the reference", "step", "m", {}, false};
  for (const std::string run : {"reference", "mi", "oldest"})
    count_panel.series.push_back({run, {0, 1, 2}, {1, 2, 3}});
  for (const std::string run : {"mi", "oldest"})
    error_panel.series.push_back({run, {0, 1}, {0, 1}});
  const std::string path = (dir / "runs.png").string();
  const auto legend = writeChartPng(path, {count_panel, error_panel});
  ASSERT_EQ(legend.size(), 5u);
  std::map<std::string, std::array<unsigned char, 3>> colour;
  for (const auto& m : legend) {
    // One colour a run over every panel, distinct between runs...
    const auto [it, first] = colour.emplace(m.name, m.bgr);
    EXPECT_TRUE(first || it->second == m.bgr) << m.name << " in panel " << m.panel;
    // ...and it is what the picture shows at the legend entry.
    const cv::Mat img = cv::imread(path);
    const auto px = img.at<cv::Vec3b>(m.y, m.x);
    EXPECT_EQ(px, cv::Vec3b(m.bgr[0], m.bgr[1], m.bgr[2])) << m.name << " in panel " << m.panel;
  }
  ASSERT_EQ(colour.size(), 3u);
  EXPECT_NE(colour["reference"], colour["mi"]);
  EXPECT_NE(colour["mi"], colour["oldest"]);
  // The first series takes the palette's first colour (blue), as before.
  EXPECT_EQ(colour["reference"], (std::array<unsigned char, 3>{180, 119, 31}));
  EXPECT_EQ(colour["mi"], (std::array<unsigned char, 3>{14, 127, 255}));
}
