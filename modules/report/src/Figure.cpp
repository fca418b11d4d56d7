#include "budget_slam/report/Figure.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <cmath>
#include <cstdio>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"

namespace budget_slam::report {
namespace {

constexpr const char* kFont = "DejaVu Sans";

/// cairo's write callback: appends to a std::string.
cairo_status_t appendTo(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void setDash(cairo_t* cr, Dash dash, double line_width) {
  const double dashed[] = {4 * line_width + 2, 2 * line_width + 1.5};
  const double dotted[] = {0.01, 2 * line_width + 1};
  switch (dash) {
    case Dash::Solid:
      cairo_set_dash(cr, nullptr, 0, 0);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
      break;
    case Dash::Dashed:
      cairo_set_dash(cr, dashed, 2, 0);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
      break;
    case Dash::Dotted:
      cairo_set_dash(cr, dotted, 2, 0);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
      break;
  }
}

void stroke(cairo_t* cr, Colour c, double line_width, Dash dash) {
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
  cairo_set_line_width(cr, line_width);
  setDash(cr, dash, line_width);
  cairo_stroke(cr);
}

}  // namespace

std::string figureFile(const std::string& stem, FigureFormat format) {
  return stem + extensionOf(format);
}

void loadFigureFonts() {
  static const bool loaded = [] {
    Figure probe(1, 1);
    probe.textWidth("0", 8, false);
    return true;
  }();
  (void)loaded;
}

Figure::Figure(double width, double height) : width_(width), height_(height) {
  const cairo_rectangle_t extents = {0, 0, width, height};
  recording_ = cairo_recording_surface_create(CAIRO_CONTENT_COLOR_ALPHA, &extents);
  cr_ = cairo_create(recording_);
  shapes_ = cairo_recording_surface_create(CAIRO_CONTENT_COLOR_ALPHA, &extents);
  shapes_cr_ = cairo_create(shapes_);
  // Text laid out at its size in points, not fitted to a screen's pixel grid: the same spacing at
  // every resolution and in the vector formats.
  cairo_font_options_t* fonts = cairo_font_options_create();
  cairo_font_options_set_hint_metrics(fonts, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_hint_style(fonts, CAIRO_HINT_STYLE_NONE);
  cairo_set_font_options(cr_, fonts);
  cairo_font_options_destroy(fonts);
  both([](cairo_t* cr) {
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
  });
}

Figure::~Figure() {
  cairo_destroy(shapes_cr_);
  cairo_surface_destroy(shapes_);
  cairo_destroy(cr_);
  cairo_surface_destroy(recording_);
}

void Figure::polyline(const std::vector<Point>& points, Colour c, double line_width, Dash dash) {
  if (points.size() < 2) return;
  both([&](cairo_t* cr) {
    cairo_move_to(cr, points[0].x, points[0].y);
    for (std::size_t i = 1; i < points.size(); ++i) cairo_line_to(cr, points[i].x, points[i].y);
    stroke(cr, c, line_width, dash);
  });
}

void Figure::line(Point a, Point b, Colour c, double line_width, Dash dash) {
  polyline({a, b}, c, line_width, dash);
}

void Figure::rectangle(Point top_left, double w, double h, Colour c, double line_width) {
  both([&](cairo_t* cr) {
    cairo_rectangle(cr, top_left.x, top_left.y, w, h);
    stroke(cr, c, line_width, Dash::Solid);
  });
}

void Figure::disc(Point centre, double radius, Colour c) {
  both([&](cairo_t* cr) {
    cairo_new_sub_path(cr);
    cairo_arc(cr, centre.x, centre.y, radius, 0, 2 * M_PI);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_fill(cr);
  });
}

void Figure::ellipse(Point centre, double a, double b, double angle, Colour c, double line_width) {
  if (!(a > 0) || !(b > 0)) return;
  both([&](cairo_t* cr) {
    cairo_save(cr);
    cairo_translate(cr, centre.x, centre.y);
    cairo_rotate(cr, -angle);  // y down: counter-clockwise on paper is a negative angle
    cairo_scale(cr, a, b);
    cairo_new_sub_path(cr);
    cairo_arc(cr, 0, 0, 1, 0, 2 * M_PI);
    cairo_restore(cr);  // the stroke in unscaled points
    stroke(cr, c, line_width, Dash::Solid);
  });
}

void Figure::plus(Point p, double half, Colour c, double line_width) {
  both([&](cairo_t* cr) {
    cairo_move_to(cr, p.x - half, p.y);
    cairo_line_to(cr, p.x + half, p.y);
    cairo_move_to(cr, p.x, p.y - half);
    cairo_line_to(cr, p.x, p.y + half);
    stroke(cr, c, line_width, Dash::Solid);
  });
}

void Figure::cross(Point p, double half, Colour c, double line_width) {
  both([&](cairo_t* cr) {
    cairo_move_to(cr, p.x - half, p.y - half);
    cairo_line_to(cr, p.x + half, p.y + half);
    cairo_move_to(cr, p.x - half, p.y + half);
    cairo_line_to(cr, p.x + half, p.y - half);
    stroke(cr, c, line_width, Dash::Solid);
  });
}

void Figure::text(Point p, const std::string& s, double size, Colour c, Align align, bool bold) {
  cairo_select_font_face(cr_, kFont, CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size);
  double x = p.x;
  if (align != Align::Left) {
    const double w = textWidth(s, size, bold);
    x -= align == Align::Centre ? w / 2 : w;
  }
  cairo_move_to(cr_, x, p.y);
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  cairo_show_text(cr_, s.c_str());
  cairo_new_path(cr_);
  cairo_matrix_t m;
  cairo_get_matrix(cr_, &m);
  texts_.push_back({x, p.y, size, {m.xx, m.yx, m.xy, m.yy, m.x0, m.y0}, s, c, bold});
}

void Figure::verticalText(Point p, const std::string& s, double size, Colour c) {
  cairo_save(cr_);
  cairo_translate(cr_, p.x, p.y);
  cairo_rotate(cr_, -M_PI / 2);
  text({0, 0}, s, size, c, Align::Centre);
  cairo_restore(cr_);
}

double Figure::textWidth(const std::string& s, double size, bool bold) const {
  cairo_select_font_face(cr_, kFont, CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr_, s.c_str(), &e);
  return e.x_advance;
}

void Figure::clip(Point top_left, double w, double h) {
  both([&](cairo_t* cr) {
    cairo_save(cr);
    cairo_rectangle(cr, top_left.x, top_left.y, w, h);
    cairo_clip(cr);
  });
}

void Figure::unclip() {
  both([](cairo_t* cr) { cairo_restore(cr); });
}

std::string Figure::svgWithText(const std::string& svg) const {
  const auto escaped = [](const std::string& t) {
    std::string out;
    for (const char ch : t) {
      switch (ch) {
        case '&':
          out += "&amp;";
          break;
        case '<':
          out += "&lt;";
          break;
        case '>':
          out += "&gt;";
          break;
        case '"':
          out += "&quot;";
          break;
        default:
          out += ch;
      }
    }
    return out;
  };
  const auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return std::string(b);
  };
  std::string g = "<g font-family=\"" + std::string(kFont) + "\" xml:space=\"preserve\">\n";
  for (const auto& t : texts_) {
    const auto channel = [&](double v) {
      return std::to_string(static_cast<int>(std::lround(255 * v)));
    };
    g += "<text x=\"" + num(t.x) + "\" y=\"" + num(t.y) + "\" font-size=\"" + num(t.size) + "\"" +
         (t.bold ? " font-weight=\"bold\"" : "") + " fill=\"rgb(" + channel(t.colour.r) + "," +
         channel(t.colour.g) + "," + channel(t.colour.b) + ")\" transform=\"matrix(";
    for (int k = 0; k < 6; ++k) g += (k ? " " : "") + num(t.matrix[k]);
    g += ")\">" + escaped(t.text) + "</text>\n";
  }
  g += "</g>\n";
  const auto end = svg.rfind("</svg>");
  if (end == std::string::npos) return svg;  // not cairo's document: left as it is
  return svg.substr(0, end) + g + svg.substr(end);
}

void Figure::write(const std::string& path, FigureFormat format, double dpi) const {
  cairo_surface_flush(recording_);
  cairo_surface_flush(shapes_);
  std::string bytes;
  cairo_surface_t* target = nullptr;
  if (format == FigureFormat::Png) {
    const int w = static_cast<int>(std::ceil(width_ * dpi / 72)),
              h = static_cast<int>(std::ceil(height_ * dpi / 72));
    target = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  } else if (format == FigureFormat::Pdf) {
    target = cairo_pdf_surface_create_for_stream(appendTo, &bytes, width_, height_);
  } else {
    target = cairo_svg_surface_create_for_stream(appendTo, &bytes, width_, height_);
    cairo_svg_surface_restrict_to_version(target, CAIRO_SVG_VERSION_1_1);
  }
  cairo_t* cr = cairo_create(target);
  if (format == FigureFormat::Png) {
    cairo_scale(cr, dpi / 72, dpi / 72);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
  }
  // cairo's SVG draws text as glyph outlines: the SVG takes the drawing without its text, and
  // the text as <text> elements on top (svgWithText).
  cairo_set_source_surface(cr, format == FigureFormat::Svg ? shapes_ : recording_, 0, 0);
  cairo_paint(cr);
  cairo_status_t status = cairo_status(cr);
  cairo_destroy(cr);
  if (format == FigureFormat::Png && status == CAIRO_STATUS_SUCCESS)
    status = cairo_surface_write_to_png_stream(target, appendTo, &bytes);
  cairo_surface_finish(target);  // PDF and SVG: the document's end is written now
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(target);
  cairo_surface_destroy(target);
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error("cannot draw '" + path + "' (" + cairo_status_to_string(status) + ")");
  writeFileAtomically(path, format == FigureFormat::Svg ? svgWithText(bytes) : bytes);
}

}  // namespace budget_slam::report
