#include "budget_slam/report/Pictures.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <vector>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"

namespace budget_slam::report {
namespace {

const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrey(150, 150, 150),
    kLight(225, 225, 225), kBlue(200, 80, 20), kRed(30, 30, 220), kGreen(40, 150, 40),
    kPathRed(0, 0, 235), kPathOrange(0, 150, 255);

/// Distinct colours (BGR) for series and clusters.
cv::Scalar palette(std::size_t i) {
  static const cv::Scalar p[] = {{180, 119, 31},  {14, 127, 255}, {44, 160, 44},   {40, 39, 214},
                                 {189, 103, 148}, {75, 86, 140},  {194, 119, 227}, {127, 127, 127},
                                 {34, 189, 188},  {207, 190, 23}};
  return p[i % (sizeof p / sizeof p[0])];
}

std::string tick(double v) {
  if (std::abs(v) < 1e-9) v = 0;  // no "-0" from accumulated round-off
  std::ostringstream o;
  o << std::setprecision(4) << v;
  return o.str();
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `n` ticks over `span`.
double niceStep(double span, int n) {
  if (!(span > 0)) return 1;
  const double raw = span / n, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

/// World (metres) to pixels with equal scale on both axes, y up.
struct Frame {
  double x0, y0, scale;
  int left, bottom;
  cv::Point operator()(double x, double y) const {
    return {static_cast<int>(std::lround(left + (x - x0) * scale)),
            static_cast<int>(std::lround(bottom - (y - y0) * scale))};
  }
};

void text(cv::Mat& img, const std::string& s, cv::Point p, double size = 0.45,
          cv::Scalar c = kBlack) {
  cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, size, c, 1, cv::LINE_AA);
}

void legendRow(cv::Mat& img, int& y, int x, const std::string& label, cv::Scalar c, int marker) {
  if (marker == 0)
    cv::line(img, {x, y - 4}, {x + 22, y - 4}, c, 2, cv::LINE_AA);
  else if (marker == 1)
    cv::circle(img, {x + 11, y - 4}, 4, c, cv::FILLED, cv::LINE_AA);
  else
    cv::drawMarker(img, {x + 11, y - 4}, c, cv::MARKER_TILTED_CROSS, 9, 2);
  text(img, label, {x + 30, y});
  y += 20;
}

/// PNG-encodes `img` and writes it atomically: a reader never sees a half-written picture.
void writePng(const std::string& path, const cv::Mat& img) {
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", img, png)) throw Error("cannot write '" + path + "' (PNG encoding)");
  writeFileAtomically(path,
                      std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

bool finite(double x, double y) { return std::isfinite(x) && std::isfinite(y); }

}  // namespace

std::array<std::uint8_t, 3> paletteRgb(std::size_t i) {
  const cv::Scalar bgr = palette(i);
  return {static_cast<std::uint8_t>(bgr[2]), static_cast<std::uint8_t>(bgr[1]),
          static_cast<std::uint8_t>(bgr[0])};
}

void writeMapPng(const std::string& path, const MapContent& c, int width, int max_height) {
  // Non-finite positions (a diverged estimate) have no place on a map: OpenCV would turn them
  // into arbitrary pixels. The caller leaves them out; anything else is a bug, reported.
  const auto reject = [&](const std::string& what) {
    throw Error("cannot draw '" + path + "': " + what + " is not finite");
  };
  for (const auto& p : c.trajectory)
    if (!finite(p.x, p.y)) reject("a trajectory pose");
  for (const auto& p : c.ground_truth_path)
    if (!finite(p.x, p.y)) reject("a ground-truth pose");
  for (const auto& l : c.kept)
    if (!l.mean.allFinite() || !l.cov.allFinite()) reject("landmark " + std::to_string(l.id));
  for (const auto& d : c.dropped)
    if (!d.allFinite()) reject("a dropped landmark");
  for (const auto& g : c.ground_truth_landmarks)
    if (!g.allFinite()) reject("a ground-truth landmark");
  double minx = std::numeric_limits<double>::infinity(), maxx = -minx, miny = minx, maxy = -minx;
  const auto grow = [&](double x, double y) {
    minx = std::min(minx, x), maxx = std::max(maxx, x);
    miny = std::min(miny, y), maxy = std::max(maxy, y);
  };
  for (const auto& p : c.trajectory) grow(p.x, p.y);
  for (const auto& p : c.ground_truth_path) grow(p.x, p.y);
  for (const auto& l : c.kept) grow(l.mean.x(), l.mean.y());
  for (const auto& d : c.dropped) grow(d.x(), d.y());
  for (const auto& g : c.ground_truth_landmarks) grow(g.x(), g.y());
  if (!std::isfinite(minx)) minx = miny = -1, maxx = maxy = 1;
  if (!std::isfinite(maxx - minx) || !std::isfinite(maxy - miny)) reject("the map's extent");
  const double pad = 0.05 * std::max({maxx - minx, maxy - miny, 1.0});
  minx -= pad, maxx += pad, miny -= pad, maxy += pad;

  // The picture takes the map's aspect ratio (equal scale on both axes), within [400, max_height].
  const int left = 70, right = 20, top = 150, bottom = 60;
  const int height = std::clamp(
      top + bottom + static_cast<int>((width - left - right) * (maxy - miny) / (maxx - minx)), 400,
      std::max(400, max_height));
  cv::Mat img(height, width, CV_8UC3, kWhite);
  const double scale =
      std::min((width - left - right) / (maxx - minx), (height - top - bottom) / (maxy - miny));
  const Frame f{minx, miny, scale, left, height - bottom};

  // Grid with metre ticks.
  const double step = niceStep(std::max(maxx - minx, maxy - miny), 8);
  for (double x = std::ceil(minx / step) * step; x <= maxx; x += step) {
    cv::line(img, f(x, miny), f(x, maxy), kLight, 1);
    text(img, tick(x), f(x, miny) + cv::Point(-12, 18), 0.4, kGrey);
  }
  for (double y = std::ceil(miny / step) * step; y <= maxy; y += step) {
    cv::line(img, f(minx, y), f(maxx, y), kLight, 1);
    text(img, tick(y), f(minx, y) + cv::Point(-55, 4), 0.4, kGrey);
  }
  text(img, "x [m]", {width / 2, height - 15}, 0.5, kGrey);
  text(img, "y [m]", {10, top - 15}, 0.5, kGrey);

  for (const auto& g : c.ground_truth_landmarks)
    cv::drawMarker(img, f(g.x(), g.y()), kGrey, cv::MARKER_CROSS, 7, 1);
  // The path, coloured by the map landmarks in view at the pose a segment ends at.
  const bool by_count = c.trajectory_landmarks.size() == c.trajectory.size();
  const auto path_colour = [&](std::size_t i) {
    if (!by_count) return kBlue;
    const std::size_t n = c.trajectory_landmarks[i];
    return n < c.min_landmarks ? kPathRed : n < 2 * c.min_landmarks ? kPathOrange : kBlue;
  };
  for (std::size_t i = 1; i < c.trajectory.size(); ++i)
    cv::line(img, f(c.trajectory[i - 1].x, c.trajectory[i - 1].y),
             f(c.trajectory[i].x, c.trajectory[i].y), path_colour(i), 2, cv::LINE_AA);
  if (by_count && c.trajectory.size() == 1)
    cv::circle(img, f(c.trajectory[0].x, c.trajectory[0].y), 3, path_colour(0), cv::FILLED);
  for (std::size_t i = 1; i < c.ground_truth_path.size(); ++i)
    cv::line(img, f(c.ground_truth_path[i - 1].x, c.ground_truth_path[i - 1].y),
             f(c.ground_truth_path[i].x, c.ground_truth_path[i].y), kBlack, 1, cv::LINE_AA);
  for (const auto& d : c.dropped)
    cv::drawMarker(img, f(d.x(), d.y()), kRed, cv::MARKER_TILTED_CROSS, 7, 1);

  for (std::size_t i = 0; i < c.kept.size(); ++i) {
    const auto& l = c.kept[i];
    const cv::Scalar colour = i < c.cluster_of_kept.size()
                                  ? palette(static_cast<std::size_t>(c.cluster_of_kept[i]))
                                  : kGreen;
    // 2-sigma ellipse from the eigen-decomposition of the 2x2 covariance.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(l.cov);
    if (es.info() == Eigen::Success && es.eigenvalues().minCoeff() > 0) {
      // Axes in pixels, bounded: a huge covariance must not overflow OpenCV's int sizes.
      const double a = std::min(2 * std::sqrt(es.eigenvalues()(1)) * scale, 1e5),
                   b = std::min(2 * std::sqrt(es.eigenvalues()(0)) * scale, 1e5);
      const Eigen::Vector2d v = es.eigenvectors().col(1);
      const double angle = -std::atan2(v.y(), v.x()) * 180 / M_PI;
      cv::ellipse(img, f(l.mean.x(), l.mean.y()),
                  cv::Size(std::max(1, static_cast<int>(a)), std::max(1, static_cast<int>(b))),
                  angle, 0, 360, colour, 1, cv::LINE_AA);
    }
    cv::circle(img, f(l.mean.x(), l.mean.y()), 3, colour, cv::FILLED, cv::LINE_AA);
  }

  text(img, c.title, {left, 30}, 0.6);
  int y = 60;
  const int lx = left;
  if (by_count) {
    const std::string k = std::to_string(c.min_landmarks), k2 = std::to_string(2 * c.min_landmarks);
    legendRow(img, y, lx, "estimated trajectory: >= " + k2 + " final-map landmarks in view", kBlue,
              0);
    legendRow(img, y, lx, k + " to " + std::to_string(2 * c.min_landmarks - 1) + " in view",
              kPathOrange, 0);
    legendRow(img, y, lx, "fewer than " + k + " in view (cannot relocalize)", kPathRed, 0);
  } else {
    legendRow(img, y, lx, "estimated trajectory", kBlue, 0);
  }
  if (!c.ground_truth_path.empty()) legendRow(img, y, lx, "ground truth", kBlack, 0);
  legendRow(img, y, lx,
            "kept landmark (2 sigma)" +
                std::string(c.cluster_of_kept.empty() ? "" : ", colour: coverage cluster"),
            c.cluster_of_kept.empty() ? kGreen : palette(0), 1);
  if (!c.dropped.empty()) legendRow(img, y, lx, "dropped landmark", kRed, 2);

  writePng(path, img);
}

std::vector<LegendMark> writeChartPng(const std::string& path,
                                      const std::vector<ChartPanel>& panels, int width,
                                      int panel_height) {
  // One palette slot a series name, in the order names first appear over the panels.
  std::map<std::string, std::size_t> colour_of;
  for (const auto& panel : panels)
    for (const auto& s : panel.series) colour_of.emplace(s.name, colour_of.size());
  std::vector<LegendMark> legend;
  const int n = std::max<int>(1, static_cast<int>(panels.size()));
  cv::Mat img(n * panel_height, width, CV_8UC3, kWhite);
  for (int k = 0; k < static_cast<int>(panels.size()); ++k) {
    const auto& panel = panels[k];
    const int top = k * panel_height + 40, bottom = (k + 1) * panel_height - 50, left = 80,
              right = width - 220;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    const auto ty = [&](double v) { return panel.log_y ? std::log10(v) : v; };
    for (const auto& s : panel.series)
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.y[i]) || (panel.log_y && s.y[i] <= 0)) continue;
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, ty(s.y[i])), y1 = std::max(y1, ty(s.y[i]));
      }
    if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (x1 <= x0) x1 = x0 + 1;
    if (!panel.log_y) y0 = std::min(y0, 0.0);
    if (y1 <= y0) y1 = y0 + 1;
    y1 += 0.05 * (y1 - y0);
    const auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * (right - left); };
    const auto py = [&](double y) { return bottom - (ty(y) - y0) / (y1 - y0) * (bottom - top); };

    cv::rectangle(img, {left, top}, {right, bottom}, kGrey, 1);
    const double xs = niceStep(x1 - x0, 8);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1; x += xs) {
      cv::line(img, {int(px(x)), top}, {int(px(x)), bottom}, kLight, 1);
      text(img, tick(x), {int(px(x)) - 12, bottom + 18}, 0.4, kGrey);
    }
    const double ys = niceStep(y1 - y0, 6);
    for (double yv = std::ceil(y0 / ys) * ys; yv <= y1; yv += ys) {
      const int yp = static_cast<int>(bottom - (yv - y0) / (y1 - y0) * (bottom - top));
      cv::line(img, {left, yp}, {right, yp}, kLight, 1);
      text(img, panel.log_y ? "1e" + tick(yv) : tick(yv), {8, yp + 4}, 0.4, kGrey);
    }
    text(img, panel.title + (panel.y_label.empty() ? "" : " [" + panel.y_label + "]"),
         {left, top - 12}, 0.55);
    text(img, panel.x_label, {(left + right) / 2, bottom + 40}, 0.45, kGrey);

    int ly = top + 15;
    for (std::size_t si = 0; si < panel.series.size(); ++si) {
      const auto& s = panel.series[si];
      const cv::Scalar colour = palette(colour_of.at(s.name));
      cv::Point prev;
      bool have = false;
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.y[i]) || (panel.log_y && s.y[i] <= 0)) {
          have = false;
          continue;
        }
        const cv::Point p(static_cast<int>(px(s.x[i])), static_cast<int>(py(s.y[i])));
        if (have) cv::line(img, prev, p, colour, 2, cv::LINE_AA);
        prev = p;
        have = true;
      }
      // legendRow draws the line from x to x + 22 at y - 4 (marker 0).
      legend.push_back(
          {static_cast<std::size_t>(k),
           s.name,
           right + 15 + 11,
           ly - 4,
           {static_cast<unsigned char>(colour[0]), static_cast<unsigned char>(colour[1]),
            static_cast<unsigned char>(colour[2])}});
      legendRow(img, ly, right + 15, s.name, colour, 0);
    }
  }
  writePng(path, img);
  return legend;
}

}  // namespace budget_slam::report
