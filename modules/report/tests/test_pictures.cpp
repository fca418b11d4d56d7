#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "budget_slam/report/Pictures.h"

using namespace budget_slam;
using namespace budget_slam::report;
namespace fs = std::filesystem;

namespace {

/// A PNG's pixels, read back with cairo.
struct Png {
  int width = 0, height = 0;
  std::vector<std::array<int, 3>> rgb;  ///< row after row
  explicit Png(const std::string& path) {
    cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
    EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS) << path;
    width = cairo_image_surface_get_width(s), height = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    for (int r = 0; r < height; ++r)
      for (int c = 0; c < width; ++c) {
        const auto px = *reinterpret_cast<const std::uint32_t*>(data + r * stride + 4 * c);
        rgb.push_back({int(px >> 16 & 255), int(px >> 8 & 255), int(px & 255)});
      }
    cairo_surface_destroy(s);
  }
  std::array<int, 3> at(int x, int y) const { return rgb[std::size_t(y) * width + x]; }
  /// Pixels of exactly `c` within rows [y0, y1) (all rows by default).
  int count(Colour c, int y0 = 0, int y1 = -1) const {
    const std::array<int, 3> want = {int(std::lround(c.r * 255)), int(std::lround(c.g * 255)),
                                     int(std::lround(c.b * 255))};
    int n = 0;
    for (int y = y0; y < (y1 < 0 ? height : y1); ++y)
      for (int x = 0; x < width; ++x) n += at(x, y) == want;
    return n;
  }
};

fs::path dir() {
  const auto d = fs::temp_directory_path() / "budget_slam_pictures";
  fs::create_directories(d);
  return d;
}

Colour cluster(std::size_t i) {
  const auto c = clusterRgb(i);
  return Colour::rgb(c[0], c[1], c[2]);
}

int px(double pt) { return static_cast<int>(std::lround(pt * kPngDpi / 72)); }

}  // namespace

TEST(Pictures, MapIsOneColumnWideAt300DpiWithEveryPart) {
  MapContent c;
  c.title = "test map";
  for (int k = 0; k <= 20; ++k) c.trajectory.push_back({0.5 * k, std::sin(0.3 * k), 0});
  LandmarkView l;
  l.mean = {3, 2};
  l.cov << 0.04, 0.01, 0.01, 0.09;
  c.kept = {l};
  const std::string plain = (dir() / "plain.png").string();
  writeMapFigure(plain, c, FigureFormat::Png);
  const Png a(plain);
  EXPECT_EQ(a.width, px(kColumnWidthPt));               // 3.5 in at 300 dpi: 1050 px
  EXPECT_GT(a.count(map_colours::kPathGood), 1000);     // the path, 0.9 pt wide
  EXPECT_GT(a.count(map_colours::kKeptNoCluster), 50);  // the landmark's disc and ellipse
  const int grey_without = a.count(map_colours::kDropped);
  EXPECT_EQ(mapLegend(c),
            (std::vector<std::string>{"estimated path", "kept landmark, 2-sigma ellipse"}));

  c.dropped = {{1, -2}, {8, 3}};
  c.ground_truth_landmarks = {{3.1, 2.1}, {5, -1}};
  c.ground_truth_path = c.trajectory;
  const std::string with = (dir() / "dropped.png").string();
  writeMapFigure(with, c, FigureFormat::Png);
  const Png b(with);
  EXPECT_GT(b.count(map_colours::kDropped), grey_without + 30);
  EXPECT_GT(b.count(map_colours::kTruthLandmark), 30);
  EXPECT_EQ(mapLegend(c), (std::vector<std::string>{
                              "estimated path", "ground-truth path", "ground-truth landmark",
                              "kept landmark, 2-sigma ellipse", "dropped landmark"}));
}

TEST(Pictures, MapColoursThePathByLandmarksInViewInColoursNoClusterHas) {
  MapContent c;
  for (int k = 0; k <= 20; ++k) c.trajectory.push_back({0.5 * k, 0, 0});
  c.trajectory_landmarks.assign(21, 5);  // all >= 2k: blue
  const std::string blue = (dir() / "blue.png").string();
  writeMapFigure(blue, c, FigureFormat::Png);
  const int red_in_legend = Png(blue).count(map_colours::kPathNone);
  for (int k = 11; k <= 20; ++k) c.trajectory_landmarks[k] = k < 16 ? 1 : 3;
  // Clusters: the kept landmarks' colours are none of the path's.
  for (int i = 0; i < 7; ++i) {
    LandmarkView l;
    l.mean = {1.0 + i, 1};
    l.cov << 0.01, 0, 0, 0.01;
    c.kept.push_back(l);
    c.cluster_of_kept.push_back(i);
    for (const Colour path : {map_colours::kPathGood, map_colours::kPathFew, map_colours::kPathNone,
                              map_colours::kDropped, map_colours::kTruthLandmark})
      EXPECT_FALSE(cluster(i) == path) << i;
  }
  const std::string mixed = (dir() / "mixed.png").string();
  writeMapFigure(mixed, c, FigureFormat::Png);
  const Png img(mixed);
  EXPECT_GT(img.count(map_colours::kPathNone), red_in_legend + 200);  // five segments below k
  EXPECT_GT(img.count(map_colours::kPathFew), 200);
  EXPECT_GT(img.count(map_colours::kPathGood), 200);
  for (int i = 0; i < 7; ++i) EXPECT_GT(img.count(cluster(i)), 20) << i;
  const auto legend = mapLegend(c);
  ASSERT_EQ(legend.size(), 4u);
  // Shares of the 21 poses: 11 with 5 in view, 5 with 1, 5 with 3.
  EXPECT_EQ(legend[0], "path, >= 4 map landmarks in view (52% of poses)");
  EXPECT_EQ(legend[1], "path, 2 to 3 in view (24% of poses)");
  EXPECT_EQ(legend[2], "path, < 2 in view: cannot relocalize (24% of poses)");
  EXPECT_EQ(legend[3], "kept landmark, 2-sigma ellipse, colour: coverage cluster");
}

TEST(Pictures, ChartIsTwoColumnsWideDrawsEverySeriesAndSkipsNan) {
  ChartPanel p{"landmarks", "step", "count", {}, false, {}};
  p.series.push_back({"a", {0, 1, 2, 3}, {1, 2, NAN, 4}});
  p.series.push_back({"b", {0, 1, 2, 3}, {4, 3, 2, 1}});
  const std::string path = (dir() / "chart.png").string();
  const auto legend = writeChart(path, "two series", {p, p}, FigureFormat::Png);
  const Png img(path);
  EXPECT_EQ(img.width, px(kPageWidthPt));  // 7.16 in at 300 dpi
  EXPECT_GT(img.count(seriesColour(0)), 300);
  EXPECT_GT(img.count(seriesColour(1)), 300);
  ASSERT_EQ(legend.size(), 4u);
}

TEST(Pictures, LinesOnOneAnotherStayVisibleAndTheReferenceIsOnTop) {
  // compare's landmarks panel: three capped runs at the cap for the whole second half, and the
  // unreduced reference above them. Each must show where they coincide.
  ChartPanel p{"landmarks in the map", "step", "landmarks", {}, false, {{20, "cap 20"}}, true};
  Series ref{"reference", {}, {}, true};
  std::vector<Series> runs = {{"mi", {}, {}}, {"coverage", {}, {}}, {"oldest", {}, {}}};
  for (int k = 0; k <= 100; ++k) {
    ref.x.push_back(k), ref.y.push_back(k * 0.4);
    for (auto& r : runs) r.x.push_back(k), r.y.push_back(std::min(20.0, k * 0.4));
  }
  p.series.push_back(ref);
  for (auto& r : runs) p.series.push_back(r);
  const std::string path = (dir() / "overlap.png").string();
  const auto legend = writeChart(path, "", {p}, FigureFormat::Png);
  const Png img(path);
  ASSERT_EQ(legend.size(), 4u);
  // Widest first: mi under coverage under oldest, each visible as a stripe along the cap.
  EXPECT_GT(legend[1].line_width, legend[2].line_width);
  EXPECT_GT(legend[2].line_width, legend[3].line_width);
  // The row where the narrowest (last) stripe runs along the cap, in the plot's right half.
  const auto rgb = [](Colour c) {
    return std::array<int, 3>{int(std::lround(c.r * 255)), int(std::lround(c.g * 255)),
                              int(std::lround(c.b * 255))};
  };
  int y_cap = 0, most = 0;
  for (int y = 0; y < img.height; ++y) {
    int n = 0;
    for (int x = img.width / 2; x < img.width * 3 / 4; ++x)
      n += img.at(x, y) == rgb(seriesColour(2));
    if (n > most) most = n, y_cap = y;
  }
  ASSERT_GT(most, 100);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_GT(img.count(seriesColour(i), y_cap - px(2), y_cap + px(2)), 200) << runs[i].name;
  // The reference: black, dashed, over the others, in the left half (where it is alone above
  // nothing) and in the legend.
  EXPECT_GT(img.count({0, 0, 0}), 500);
  EXPECT_EQ(legend[0].name, "reference");
  EXPECT_EQ(legend[0].colour, (Colour{0, 0, 0}));
  // Each legend sample shows its colour along its line (the reference's is dashed).
  for (const auto& m : legend) {
    int n = 0;
    for (int x = px(m.at.x - 7); x <= px(m.at.x + 7); ++x)
      n += img.at(x, px(m.at.y)) == rgb(m.colour);
    EXPECT_GT(n, px(7)) << m.name;
  }
}

TEST(Pictures, ChartKeepsOneColourARunAcrossPanels) {
  // compare without ground truth: the upper panel has every run, the lower one no reference
  // (it shows the difference to the reference). mi must keep its colour in both panels.
  ChartPanel count_panel{"landmarks", "step", "landmarks", {}, false, {}};
  ChartPanel error_panel{"difference to the reference", "step", "m", {}, false, {}};
  count_panel.series.push_back({"reference", {0, 1, 2}, {1, 2, 3}, true});
  for (const std::string run : {"mi", "oldest"}) {
    count_panel.series.push_back({run, {0, 1, 2}, {1, 2, 3}});
    error_panel.series.push_back({run, {0, 1}, {0, 1}});
  }
  const auto legend =
      writeChart((dir() / "runs.png").string(), "", {count_panel, error_panel}, FigureFormat::Png);
  ASSERT_EQ(legend.size(), 5u);
  std::map<std::string, Colour> colour;
  for (const auto& m : legend) {
    const auto [it, first] = colour.emplace(m.name, m.colour);
    EXPECT_TRUE(first || it->second == m.colour) << m.name << " in panel " << m.panel;
  }
  ASSERT_EQ(colour.size(), 3u);
  EXPECT_EQ(colour["mi"], seriesColour(0));  // the first reducer takes the first colour
  EXPECT_EQ(colour["oldest"], seriesColour(1));
}

TEST(Pictures, VectorFormatsAreWritten) {
  MapContent c;
  c.title = "vector";
  for (int k = 0; k <= 5; ++k) c.trajectory.push_back({double(k), 0, 0});
  const auto pdf = (dir() / "v.pdf").string(), svg = (dir() / "v.svg").string();
  writeMapFigure(pdf, c, FigureFormat::Pdf);
  writeMapFigure(svg, c, FigureFormat::Svg);
  std::ifstream p(pdf), s(svg);
  std::string head(5, ' ');
  p.read(head.data(), 5);
  EXPECT_EQ(head, "%PDF-");
  std::string text((std::istreambuf_iterator<char>(s)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("width=\"252pt\""), std::string::npos);  // one column, in points
  // Text as text (issue 35: cairo drew it as glyph outlines, 0 <text> elements): the title is a
  // <text> element in DejaVu Sans, and no glyph outline is left.
  EXPECT_NE(text.find(">vector</text>"), std::string::npos);
  EXPECT_NE(text.find("font-family=\"DejaVu Sans\""), std::string::npos);
  EXPECT_EQ(text.find("<symbol"), std::string::npos);
  EXPECT_EQ(text.find("id=\"glyph"), std::string::npos);
}
