#pragma once
// The figures of a run and a comparison (docs/OUTPUTS.md, "Figures"): map.<ext> one paper column
// wide, comparison.<ext> two columns wide, each as PNG, PDF or SVG ([Report] figure_format).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/report/Figure.h"

namespace budget_slam::report {

/// What the map figure shows (docs/OUTPUTS.md): the trajectory (and ground truth), the kept
/// landmarks with their 2-sigma ellipses, the dropped landmarks, and the coverage clusters in
/// colour.
struct MapContent {
  std::string title;
  std::vector<Pose2> trajectory;
  std::vector<Pose2> ground_truth_path;                 ///< in the estimate's frame
  std::vector<Eigen::Vector2d> ground_truth_landmarks;  ///< in the estimate's frame
  std::vector<LandmarkView> kept;
  std::vector<int> cluster_of_kept;      ///< cluster index per kept landmark, or empty
  std::vector<Eigen::Vector2d> dropped;  ///< where dropped landmarks were when dropped
  /// When not empty (one per trajectory pose): landmarks of the final map observed at that pose;
  /// the path is then coloured by it: red below `min_landmarks`, orange below twice that, blue.
  std::vector<std::size_t> trajectory_landmarks;
  std::size_t min_landmarks = 2;
};

/// Colours of the map figure (and map.3Dscene): the path by landmarks in view, the ground truth,
/// the dropped landmarks. None of them is a cluster colour.
namespace map_colours {
const Colour kPathGood = Colour::rgb(31, 80, 200), kPathFew = Colour::rgb(245, 140, 0),
             kPathNone = Colour::rgb(215, 25, 28), kTruth = Colour::rgb(0, 0, 0),
             kTruthLandmark = Colour::rgb(150, 150, 150), kDropped = Colour::rgb(90, 90, 90),
             kKeptNoCluster = Colour::rgb(44, 160, 44);
}  // namespace map_colours

/// The i-th coverage-cluster colour (R, G, B; cycles after 7): greens, purples, browns, pinks,
/// none the path's blue, orange or red, nor the greys of ground truth and drops.
std::array<std::uint8_t, 3> clusterRgb(std::size_t i);

/// The map figure's legend entries, in order (the text each shows).
std::vector<std::string> mapLegend(const MapContent& content);

/// Writes `content` one paper column wide (kColumnWidthPt) and as high as the map's aspect ratio
/// asks, title and legend above the map, in `format`. Written atomically. Throws Error if it
/// cannot write, or when a position is not finite (the caller leaves such ones out).
void writeMapFigure(const std::string& path, const MapContent& content, FigureFormat format);

/// One line of a chart.
struct Series {
  std::string name;
  std::vector<double> x, y;
  /// The unreduced reference: black, dashed, drawn over the others.
  bool reference = false;
};

/// A horizontal mark on a panel (the cap), with its label.
struct ChartMark {
  double y = 0;
  std::string label;
};

/// A panel of a chart.
struct ChartPanel {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  bool log_y = false;
  std::vector<ChartMark> marks;
  /// Series that often lie on one another (landmark counts at the cap): the first is drawn
  /// widest and each next one narrower over it, so every one shows as a stripe. Otherwise all
  /// are drawn 0.8 pt wide.
  bool nested_widths = false;
};

/// Where writeChart drew one legend entry, and how.
struct LegendMark {
  std::size_t panel = 0;
  std::string name;
  Point at;  ///< the middle of the entry's line [pt]
  Colour colour;
  double line_width = 0;  ///< [pt]
};

/// The i-th series colour (tab10, cycles after 10).
Colour seriesColour(std::size_t i);

/// Renders the panels stacked, two paper columns wide (kPageWidthPt), each with its legend on
/// the right, under `title`. A series keeps one colour in every panel, chosen by its name in the
/// order names first appear over the panels, so a series missing from one panel shifts no other.
/// The reference is drawn dashed black over the others (and, with nested_widths, lines lying on
/// one another stay visible as stripes). Returns the legend entries it drew.
/// Throws Error if it cannot write.
std::vector<LegendMark> writeChart(const std::string& path, const std::string& title,
                                   const std::vector<ChartPanel>& panels, FigureFormat format);

}  // namespace budget_slam::report
