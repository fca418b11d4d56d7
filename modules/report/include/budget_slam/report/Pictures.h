#pragma once
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"

namespace budget_slam::report {

/// What map.png shows (docs/OUTPUTS.md): the trajectory (and ground truth), the kept landmarks
/// with their 2-sigma ellipses, the dropped landmarks, and the coverage clusters in colour.
struct MapContent {
  std::string title;
  std::vector<mrpt::math::TPose2D> trajectory;
  std::vector<mrpt::math::TPose2D> ground_truth_path;   ///< in the estimate's frame
  std::vector<Eigen::Vector2d> ground_truth_landmarks;  ///< in the estimate's frame
  std::vector<LandmarkView> kept;
  std::vector<int> cluster_of_kept;      ///< cluster index per kept landmark, or empty
  std::vector<Eigen::Vector2d> dropped;  ///< where dropped landmarks were when dropped
  /// When not empty (one per trajectory pose): landmarks of the final map observed at that pose;
  /// the path is then coloured by it: red below `min_landmarks`, orange below twice that, blue.
  std::vector<std::size_t> trajectory_landmarks;
  std::size_t min_landmarks = 2;
};

/// Renders `content` to a PNG `width` pixels wide and as high as the map's aspect ratio asks
/// (between 400 and `max_height` pixels), legend on top (OpenCV). Written atomically. Throws Error
/// if it cannot write, or when a position is not finite (the caller leaves such ones out).
void writeMapPng(const std::string& path, const MapContent& content, int width = 1000,
                 int max_height = 1400);

/// The i-th colour (R, G, B) of the palette map.png gives coverage clusters and chart series
/// (cycles after 10), so that map.3Dscene colours clusters the same.
std::array<std::uint8_t, 3> paletteRgb(std::size_t i);

/// One line of a chart.
struct Series {
  std::string name;
  std::vector<double> x, y;
};

/// A panel of a chart picture.
struct ChartPanel {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  bool log_y = false;
};

/// Where writeChartPng drew one legend entry, and in which colour.
struct LegendMark {
  std::size_t panel = 0;
  std::string name;
  int x = 0, y = 0;                    ///< a pixel in the middle of the entry's line [px]
  std::array<unsigned char, 3> bgr{};  ///< its colour, blue green red
};

/// Renders the panels stacked vertically, each with its legend (OpenCV). A series keeps one
/// colour in every panel, chosen by its name in the order names first appear over the panels,
/// so a series missing from one panel shifts no other. Returns the legend entries it drew.
/// Throws Error if it cannot write.
std::vector<LegendMark> writeChartPng(const std::string& path,
                                      const std::vector<ChartPanel>& panels, int width = 1200,
                                      int panel_height = 420);

}  // namespace budget_slam::report
