#include "budget_slam/report/Pictures.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "budget_slam/core/Error.h"

namespace budget_slam::report {
namespace {

// Type sizes [pt]: readable at 100% in a two-column paper (its body text is 9-10 pt).
constexpr double kTickSize = 6, kTextSize = 6.5, kTitleSize = 7.5, kRow = 8.5;
const Colour kBlack{0, 0, 0}, kGrid = Colour::rgb(225, 225, 225),
                              kFrame = Colour::rgb(150, 150, 150),
                              kTickText = Colour::rgb(90, 90, 90);

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

bool finite(double x, double y) { return std::isfinite(x) && std::isfinite(y); }

/// `text` broken at spaces into lines at most `width` wide (a word longer than that stays whole).
std::vector<std::string> wrap(const Figure& f, const std::string& text, double width, double size,
                              bool bold) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream words(text);
  for (std::string w; words >> w;) {
    const std::string longer = line.empty() ? w : line + " " + w;
    if (!line.empty() && f.textWidth(longer, size, bold) > width) {
      lines.push_back(line);
      line = w;
    } else {
      line = longer;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

/// A legend entry: its sample (a line, a disc, a "+", an "x", or a disc in its ellipse) and text.
struct Entry {
  enum class Mark { Line, Disc, Plus, Cross, Ellipse };
  Mark mark;
  Colour colour;
  std::string text;
  double line_width = 1;
  Dash dash = Dash::Solid;
};

/// Entries laid out in as many columns as fit `width`; returns the height they take.
double legendHeight(const Figure& f, const std::vector<Entry>& entries, double width,
                    int& columns) {
  double widest = 0;
  for (const auto& e : entries) widest = std::max(widest, f.textWidth(e.text, kTextSize));
  columns = std::clamp(static_cast<int>(width / (widest + 26)), 1, 3);
  const auto rows = (entries.size() + columns - 1) / columns;
  return rows * kRow;
}

/// Draws the entries from (x, y) (the first row's baseline), `columns` columns in `width`.
/// Returns the middle of each entry's sample.
std::vector<Point> drawLegend(Figure& f, const std::vector<Entry>& entries, double x, double y,
                              double width, int columns) {
  std::vector<Point> at;
  const double column_width = width / columns;
  const std::size_t rows = (entries.size() + columns - 1) / columns;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const auto& e = entries[i];
    const double cx = x + (i / rows) * column_width, cy = y + (i % rows) * kRow;
    const Point mid{cx + 7, cy - 2.2};
    switch (e.mark) {
      case Entry::Mark::Line:
        f.line({cx, mid.y}, {cx + 14, mid.y}, e.colour, e.line_width, e.dash);
        break;
      case Entry::Mark::Disc:
        f.disc(mid, 1.6, e.colour);
        break;
      case Entry::Mark::Plus:
        f.plus(mid, 2, e.colour, 0.6);
        break;
      case Entry::Mark::Cross:
        f.cross(mid, 1.8, e.colour, 0.6);
        break;
      case Entry::Mark::Ellipse:
        f.ellipse(mid, 5, 2.4, 0.3, e.colour, 0.5);
        f.disc(mid, 1.2, e.colour);
        break;
    }
    at.push_back(mid);
    f.text({cx + 17, cy}, e.text, kTextSize, kBlack);
  }
  return at;
}

std::string percent(std::size_t n, std::size_t of) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(of && 100.0 * n / of < 10 ? 1 : 0)
    << (of ? 100.0 * n / of : 0.0) << "% of poses";
  return o.str();
}

std::vector<Entry> mapEntries(const MapContent& c) {
  using namespace map_colours;
  std::vector<Entry> e;
  const bool by_count =
      !c.trajectory.empty() && c.trajectory_landmarks.size() == c.trajectory.size();
  if (by_count) {
    const std::size_t k = c.min_landmarks;
    std::size_t good = 0, few = 0, none = 0;
    for (const auto n : c.trajectory_landmarks) ++(n >= 2 * k ? good : n >= k ? few : none);
    const std::size_t all = c.trajectory_landmarks.size();
    e.push_back({Entry::Mark::Line, kPathGood,
                 "path, >= " + std::to_string(2 * k) + " map landmarks in view (" +
                     percent(good, all) + ")",
                 1.2});
    e.push_back({Entry::Mark::Line, kPathFew,
                 "path, " + std::to_string(k) + " to " + std::to_string(2 * k - 1) + " in view (" +
                     percent(few, all) + ")",
                 1.2});
    e.push_back({Entry::Mark::Line, kPathNone,
                 "path, < " + std::to_string(k) + " in view: cannot relocalize (" +
                     percent(none, all) + ")",
                 1.2});
  } else if (!c.trajectory.empty()) {
    e.push_back({Entry::Mark::Line, kPathGood, "estimated path", 1.2});
  }
  if (!c.ground_truth_path.empty())
    e.push_back({Entry::Mark::Line, kTruth, "ground-truth path", 0.5});
  if (!c.ground_truth_landmarks.empty())
    e.push_back({Entry::Mark::Plus, kTruthLandmark, "ground-truth landmark"});
  if (c.cluster_of_kept.empty())
    e.push_back({Entry::Mark::Ellipse, kKeptNoCluster, "kept landmark, 2-sigma ellipse"});
  else
    e.push_back({Entry::Mark::Ellipse,
                 Colour::rgb(clusterRgb(0)[0], clusterRgb(0)[1], clusterRgb(0)[2]),
                 "kept landmark, 2-sigma ellipse, colour: coverage cluster"});
  if (!c.dropped.empty()) e.push_back({Entry::Mark::Cross, kDropped, "dropped landmark"});
  return e;
}

}  // namespace

std::array<std::uint8_t, 3> clusterRgb(std::size_t i) {
  static const std::array<std::uint8_t, 3> p[] = {{44, 160, 44},   {148, 103, 189}, {140, 86, 75},
                                                  {227, 119, 194}, {188, 189, 34},  {23, 190, 207},
                                                  {0, 110, 110}};
  return p[i % (sizeof p / sizeof p[0])];
}

Colour seriesColour(std::size_t i) {
  static const Colour p[] = {Colour::rgb(31, 119, 180),  Colour::rgb(255, 127, 14),
                             Colour::rgb(44, 160, 44),   Colour::rgb(214, 39, 40),
                             Colour::rgb(148, 103, 189), Colour::rgb(140, 86, 75),
                             Colour::rgb(227, 119, 194), Colour::rgb(127, 127, 127),
                             Colour::rgb(188, 189, 34),  Colour::rgb(23, 190, 207)};
  return p[i % (sizeof p / sizeof p[0])];
}

std::vector<std::string> mapLegend(const MapContent& content) {
  std::vector<std::string> out;
  for (const auto& e : mapEntries(content)) out.push_back(e.text);
  return out;
}

void writeMapFigure(const std::string& path, const MapContent& c, FigureFormat format) {
  using namespace map_colours;
  // Non-finite positions (a diverged estimate) have no place on a map. The caller leaves them
  // out; anything else is a bug, reported.
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
  const double pad = 0.04 * std::max({maxx - minx, maxy - miny, 1.0});
  minx -= pad, maxx += pad, miny -= pad, maxy += pad;

  // Layout [pt]: title and legend on top, the map at equal scale on both axes below.
  const double W = kColumnWidthPt, left = 30, right = 6, bottom = 20, margin = 6;
  const std::vector<Entry> entries = mapEntries(c);
  std::vector<std::string> title;
  int columns = 1;
  double legend_h = 0;
  {
    const Figure measure(1, 1);
    title = wrap(measure, c.title, W - 2 * margin, kTitleSize, true);
    legend_h = legendHeight(measure, entries, W - 2 * margin, columns);
  }
  const double top = margin + title.size() * 9 + 4 + legend_h + 4;
  const double pw = W - left - right, dx = maxx - minx, dy = maxy - miny;
  const double ph = std::clamp(pw * dy / dx, 110.0, 330.0);
  Figure f(W, top + ph + bottom);
  const double scale = std::min(pw / dx, ph / dy);
  const double ox = left + (pw - dx * scale) / 2, oy = top + (ph - dy * scale) / 2;
  const auto at = [&](double x, double y) {
    return Point{ox + (x - minx) * scale, oy + (maxy - y) * scale};
  };

  // Grid with metre ticks over the whole plot area (wider or taller than the map's extent).
  const double wx0 = minx - (ox - left) / scale, wx1 = minx + (left + pw - ox) / scale,
               wy0 = maxy - (top + ph - oy) / scale, wy1 = maxy + (oy - top) / scale;
  const double step = niceStep(std::max(wx1 - wx0, wy1 - wy0), 7);
  for (double x = std::ceil(wx0 / step) * step; x <= wx1; x += step) {
    f.line(at(x, wy0), at(x, wy1), kGrid, 0.4);
    f.text({at(x, wy0).x, top + ph + 8}, tick(x), kTickSize, kTickText, Align::Centre);
  }
  for (double y = std::ceil(wy0 / step) * step; y <= wy1; y += step) {
    f.line(at(wx0, y), at(wx1, y), kGrid, 0.4);
    f.text({left - 2, at(wx0, y).y + 2}, tick(y), kTickSize, kTickText, Align::Right);
  }
  f.text({left + pw / 2, top + ph + 16}, "x [m]", kTickSize, kTickText, Align::Centre);
  f.verticalText({6, top + ph / 2}, "y [m]", kTickSize, kTickText);

  f.clip({left, top}, pw, ph);
  for (const auto& g : c.ground_truth_landmarks) f.plus(at(g.x(), g.y()), 1.6, kTruthLandmark, 0.4);
  // The true path under the estimate; the estimate in runs of one colour, coloured by the map
  // landmarks in view at each pose.
  std::vector<Point> truth;
  for (const auto& p : c.ground_truth_path) truth.push_back(at(p.x, p.y));
  f.polyline(truth, kTruth, 0.4);
  const bool by_count = c.trajectory_landmarks.size() == c.trajectory.size();
  const auto path_colour = [&](std::size_t i) {
    if (!by_count) return kPathGood;
    const std::size_t n = c.trajectory_landmarks[i];
    return n < c.min_landmarks ? kPathNone : n < 2 * c.min_landmarks ? kPathFew : kPathGood;
  };
  for (std::size_t i = 1; i < c.trajectory.size();) {
    const Colour colour = path_colour(i);
    std::vector<Point> run = {at(c.trajectory[i - 1].x, c.trajectory[i - 1].y)};
    for (; i < c.trajectory.size() && path_colour(i) == colour; ++i)
      run.push_back(at(c.trajectory[i].x, c.trajectory[i].y));
    f.polyline(run, colour, 0.9);
  }
  if (by_count && c.trajectory.size() == 1)
    f.disc(at(c.trajectory[0].x, c.trajectory[0].y), 1.2, path_colour(0));
  for (const auto& d : c.dropped) f.cross(at(d.x(), d.y()), 1.3, kDropped, 0.4);
  for (std::size_t i = 0; i < c.kept.size(); ++i) {
    const auto& l = c.kept[i];
    Colour colour = kKeptNoCluster;
    if (i < c.cluster_of_kept.size()) {
      const auto rgb = clusterRgb(static_cast<std::size_t>(c.cluster_of_kept[i]));
      colour = Colour::rgb(rgb[0], rgb[1], rgb[2]);
    }
    // 2-sigma ellipse from the eigen-decomposition of the 2x2 covariance, bounded in size.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(l.cov);
    if (es.info() == Eigen::Success && es.eigenvalues().minCoeff() > 0) {
      const double a = std::min(2 * std::sqrt(es.eigenvalues()(1)) * scale, 1e4),
                   b = std::min(2 * std::sqrt(es.eigenvalues()(0)) * scale, 1e4);
      const Eigen::Vector2d v = es.eigenvectors().col(1);
      f.ellipse(at(l.mean.x(), l.mean.y()), std::max(a, 0.3), std::max(b, 0.3),
                std::atan2(v.y(), v.x()), colour, 0.4);
    }
    f.disc(at(l.mean.x(), l.mean.y()), 1.3, colour);
  }
  f.unclip();
  f.rectangle({left, top}, pw, ph, kFrame, 0.5);

  double y = margin + kTitleSize;
  for (const auto& line : title) {
    f.text({margin, y}, line, kTitleSize, kBlack, Align::Left, true);
    y += 9;
  }
  drawLegend(f, entries, margin, y + 4, W - 2 * margin, columns);
  f.write(path, format);
}

std::vector<LegendMark> writeChart(const std::string& path, const std::string& title,
                                   const std::vector<ChartPanel>& panels, FigureFormat format) {
  // One palette slot a series name (the reference has its own black), in the order names first
  // appear over the panels.
  std::map<std::string, std::size_t> colour_of;
  double widest = 0;
  {
    const Figure measure(1, 1);
    for (const auto& panel : panels)
      for (const auto& s : panel.series) {
        if (!s.reference) colour_of.emplace(s.name, colour_of.size());
        widest = std::max(widest, measure.textWidth(s.name, kTextSize));
      }
  }
  const double W = kPageWidthPt, left = 40, legend_w = std::clamp(widest + 32, 60.0, 170.0);
  const double right = legend_w + 8, head = title.empty() ? 4 : 14, panel_h = 150, plot_top = 12,
               plot_h = panel_h - plot_top - 26;
  const std::size_t n = std::max<std::size_t>(1, panels.size());
  Figure f(W, head + n * panel_h);
  if (!title.empty()) f.text({left, 10}, title, kTitleSize, kBlack, Align::Left, true);
  std::vector<LegendMark> legend;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const auto& panel = panels[k];
    const double top = head + k * panel_h + plot_top, bottom = top + plot_h, x_right = W - right;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    const auto ty = [&](double v) { return panel.log_y ? std::log10(v) : v; };
    for (const auto& s : panel.series)
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.y[i]) || (panel.log_y && s.y[i] <= 0)) continue;
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, ty(s.y[i])), y1 = std::max(y1, ty(s.y[i]));
      }
    for (const auto& m : panel.marks)
      if (std::isfinite(m.y) && (!panel.log_y || m.y > 0))
        y0 = std::min(y0, ty(m.y)), y1 = std::max(y1, ty(m.y));
    if (!std::isfinite(x0)) x0 = 0, x1 = 1;
    if (!std::isfinite(y0)) y0 = 0, y1 = 1;
    if (x1 <= x0) x1 = x0 + 1;
    if (!panel.log_y) y0 = std::min(y0, 0.0);
    if (y1 <= y0) y1 = y0 + 1;
    y1 += 0.06 * (y1 - y0);
    const auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * (x_right - left); };
    const auto py = [&](double y) { return bottom - (ty(y) - y0) / (y1 - y0) * (bottom - top); };

    const double xs = niceStep(x1 - x0, 8);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1; x += xs) {
      f.line({px(x), top}, {px(x), bottom}, kGrid, 0.4);
      f.text({px(x), bottom + 8}, tick(x), kTickSize, kTickText, Align::Centre);
    }
    const double ys = niceStep(y1 - y0, 5);
    for (double yv = std::ceil(y0 / ys) * ys; yv <= y1; yv += ys) {
      const double yp = bottom - (yv - y0) / (y1 - y0) * (bottom - top);
      f.line({left, yp}, {x_right, yp}, kGrid, 0.4);
      f.text({left - 3, yp + 2}, panel.log_y ? "1e" + tick(yv) : tick(yv), kTickSize, kTickText,
             Align::Right);
    }
    f.text({left, top - 4}, panel.title + (panel.y_label.empty() ? "" : " [" + panel.y_label + "]"),
           kTextSize + 0.5, kBlack);
    f.text({(left + x_right) / 2, bottom + 17}, panel.x_label, kTickSize, kTickText, Align::Centre);

    // Widest first, each next series narrower over it: lines lying on one another (capped runs
    // at the cap) show as nested stripes. The reference goes on top, dashed.
    std::size_t others = 0;
    for (const auto& s : panel.series) others += !s.reference;
    const double step = panel.nested_widths && others > 1 ? std::min(1.0, 3.0 / (others - 1)) : 0;
    const double narrowest = panel.nested_widths ? 1.0 : 0.8;
    f.clip({left, top}, x_right - left, bottom - top);
    for (const auto& m : panel.marks)
      if (std::isfinite(m.y) && (!panel.log_y || m.y > 0)) {
        f.line({left, py(m.y)}, {x_right, py(m.y)}, kTickText, 0.6, Dash::Dotted);
        f.text({x_right - 2, py(m.y) - 5}, m.label, kTickSize, kTickText, Align::Right);
      }
    struct Style {
      Colour colour;
      double width;
      Dash dash;
    };
    std::vector<Style> styles;
    std::size_t rank = 0;
    for (const auto& s : panel.series) {
      if (s.reference)
        styles.push_back({kBlack, 1.0, Dash::Dashed});
      else
        styles.push_back({seriesColour(colour_of.at(s.name)),
                          narrowest + step * (others - 1 - rank++), Dash::Solid});
    }
    for (const bool reference : {false, true})
      for (std::size_t si = 0; si < panel.series.size(); ++si) {
        const auto& s = panel.series[si];
        if (s.reference != reference) continue;
        std::vector<Point> run;
        const auto flush = [&] {
          f.polyline(run, styles[si].colour, styles[si].width, styles[si].dash);
          run.clear();
        };
        for (std::size_t i = 0; i < s.x.size(); ++i) {
          if (!std::isfinite(s.y[i]) || (panel.log_y && s.y[i] <= 0)) {
            flush();
            continue;
          }
          run.push_back({px(s.x[i]), py(s.y[i])});
        }
        flush();
      }
    f.unclip();
    f.rectangle({left, top}, x_right - left, bottom - top, kFrame, 0.5);

    std::vector<Entry> entries;
    for (std::size_t si = 0; si < panel.series.size(); ++si)
      entries.push_back({Entry::Mark::Line, styles[si].colour, panel.series[si].name,
                         styles[si].width, styles[si].dash});
    const auto marks = drawLegend(f, entries, x_right + 8, top + 6, legend_w, 1);
    for (std::size_t si = 0; si < panel.series.size(); ++si)
      legend.push_back({k, panel.series[si].name, marks[si], styles[si].colour, styles[si].width});
  }
  f.write(path, format);
  return legend;
}

}  // namespace budget_slam::report
