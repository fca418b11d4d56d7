#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::report {

/// A file format of the figures (map.png, comparison.png): raster PNG, or vector PDF and SVG for
/// a paper.
enum class FigureFormat { Png, Pdf, Svg };
const EnumNames<FigureFormat>& figureFormatNames();  ///< png, pdf, svg
/// The file extension of `f`, with its dot: ".png".
std::string extensionOf(FigureFormat f);

/// [Report]: how the application reports (docs/OUTPUTS.md "Figures" and "Progress").
struct ReportOptions : public TabledOptions<ReportOptions> {
  static constexpr const char* kSection = "Report";

  /// Formats every figure is written in, comma-separated, each once: png, pdf, svg (map.png,
  /// map.pdf, ...). Default: png.
  std::vector<FigureFormat> figure_formats = {FigureFormat::Png};
  /// When stderr is not a terminal (a pipe, a log file, a batch job), a progress line this often
  /// [s]; 0: none. Default: 5.
  double progress_every_s = 5;
  /// The figures' title (map: the rawlog, backend, reducer, cap and counts; comparison: the
  /// rawlog, backend, cap, steps and seeds); false: none, for a paper whose caption says it.
  /// Default: true.
  bool figure_title = true;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<ReportOptions>& table();
};

}  // namespace budget_slam::report
