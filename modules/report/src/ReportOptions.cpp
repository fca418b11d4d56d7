#include "budget_slam/report/ReportOptions.h"

#include <algorithm>

#include "budget_slam/core/Error.h"

namespace budget_slam::report {
namespace {

/// figure_format: a list of format names, each once, at least one.
OptionKey<ReportOptions> figureFormats() {
  using O = ReportOptions;
  return {"figure_format",
          [](O& o, const IniSection& s) {
            if (!s.has("figure_format")) return;
            const auto names = s.readList("figure_format");
            const std::string where = "[" + std::string(O::kSection) +
                                      "] figure_format = " + s.readString("figure_format", "");
            if (names.empty()) throw ConfigError(where + ": give png, pdf or svg (or a list)");
            std::vector<FigureFormat> formats;
            for (const auto& n : names) {
              const FigureFormat* f = valueOf(figureFormatNames(), n);
              if (!f) throw ConfigError(where + ": '" + n + "' is not png, pdf or svg");
              if (std::find(formats.begin(), formats.end(), *f) != formats.end())
                throw ConfigError(where + ": " + n + " is listed twice");
              formats.push_back(*f);
            }
            o.figure_formats = formats;
          },
          [](const O& o) {
            std::string t;
            for (const auto f : o.figure_formats)
              t += (t.empty() ? "" : ",") + nameOf(figureFormatNames(), f);
            return t;
          },
          "png, pdf, svg, comma-separated"};
}

}  // namespace

const EnumNames<FigureFormat>& figureFormatNames() {
  static const EnumNames<FigureFormat> names = {
      {"png", FigureFormat::Png}, {"pdf", FigureFormat::Pdf}, {"svg", FigureFormat::Svg}};
  return names;
}

std::string extensionOf(FigureFormat f) { return "." + nameOf(figureFormatNames(), f); }

const OptionTable<ReportOptions>& ReportOptions::table() {
  using O = ReportOptions;
  static const OptionTable<O> t = {
      figureFormats(),
      option::real("progress_every_s", &O::progress_every_s, 0, 86400, "[s], 0: no lines"),
      option::flag("figure_title", &O::figure_title, "false: figures without a title"),
  };
  return t;
}

}  // namespace budget_slam::report
