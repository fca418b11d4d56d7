#pragma once
// A figure drawn once, in points (1/72 inch, y down), and written as PNG, PDF or SVG with cairo:
// the same drawing as a raster picture and as vector graphics for a paper (docs/OUTPUTS.md,
// "Figures").
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/report/ReportOptions.h"

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace budget_slam::report {

/// Width of one column of a two-column paper (IEEE: 3.5 in) and of both [pt].
constexpr double kColumnWidthPt = 252, kPageWidthPt = 516;
/// Resolution of a PNG figure [dots per inch].
constexpr double kPngDpi = 300;

struct Colour {
  double r = 0, g = 0, b = 0;  ///< in [0, 1]
  static Colour rgb(int r, int g, int b) { return {r / 255.0, g / 255.0, b / 255.0}; }
  bool operator==(const Colour& o) const { return r == o.r && g == o.g && b == o.b; }
};

struct Point {
  double x = 0, y = 0;  ///< [pt], y down
};

enum class Dash { Solid, Dashed, Dotted };
enum class Align { Left, Centre, Right };

class Figure {
 public:
  /// A white figure of `width` x `height` points.
  Figure(double width, double height);
  ~Figure();
  Figure(const Figure&) = delete;
  Figure& operator=(const Figure&) = delete;

  double width() const { return width_; }
  double height() const { return height_; }

  void polyline(const std::vector<Point>& points, Colour c, double line_width,
                Dash dash = Dash::Solid);
  void line(Point a, Point b, Colour c, double line_width, Dash dash = Dash::Solid);
  void rectangle(Point top_left, double w, double h, Colour c, double line_width);
  void disc(Point centre, double radius, Colour c);
  /// An ellipse of half-axes a, b, the first turned by `angle` [rad] (counter-clockwise on paper).
  void ellipse(Point centre, double a, double b, double angle, Colour c, double line_width);
  void plus(Point centre, double half, Colour c, double line_width);   ///< "+"
  void cross(Point centre, double half, Colour c, double line_width);  ///< "x"
  /// Text with its baseline at p.y, `size` [pt], in DejaVu Sans.
  void text(Point p, const std::string& s, double size, Colour c, Align align = Align::Left,
            bool bold = false);
  /// Text read from bottom to top (an axis label on the left), its baseline's middle at p.
  void verticalText(Point p, const std::string& s, double size, Colour c);
  double textWidth(const std::string& s, double size, bool bold = false) const;
  /// Drawing outside the rectangle is cut off until unclip().
  void clip(Point top_left, double w, double h);
  void unclip();

  /// Writes the figure atomically (a reader never sees a torn file): PNG at `dpi`, or PDF or SVG
  /// at its size in points. Throws Error naming the file.
  void write(const std::string& path, FigureFormat format, double dpi = kPngDpi) const;

 private:
  /// A piece of text as an SVG <text> element takes it: at (x, y) in user space (its baseline's
  /// start), under the transformation `matrix` (cairo's xx, yx, xy, yy, x0, y0) to the page.
  struct TextItem {
    double x, y, size;
    double matrix[6];
    std::string text;
    Colour colour;
    bool bold;
  };
  /// `draw` on both recordings: with the text (PNG, PDF) and without it (SVG, whose text is
  /// written as <text> elements, so that it stays text: searchable, editable, its font the
  /// reader's DejaVu Sans).
  template <class F>
  void both(F draw) {
    draw(cr_);
    draw(shapes_cr_);
  }
  std::string svgWithText(const std::string& svg) const;

  double width_, height_;
  cairo_surface_t* recording_ = nullptr;
  cairo_t* cr_ = nullptr;
  cairo_surface_t* shapes_ = nullptr;
  cairo_t* shapes_cr_ = nullptr;
  std::vector<TextItem> texts_;
};

/// Loads the fonts the figures use (fontconfig's configuration and cache files) now. Called when a
/// command starts, while file descriptors are to be had: fontconfig, first asked at the end of a
/// run under a low `ulimit -n`, prints its own "Fontconfig error" line on stderr. Once a process.
void loadFigureFonts();

/// "map" + ".png": the file name of a figure in `format`.
std::string figureFile(const std::string& stem, FigureFormat format);

}  // namespace budget_slam::report
