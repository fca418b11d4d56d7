// read_summary, summary_keys and exit_code: the run layer's typed outcome in summary.json's words
// (engine/SummaryJson.h, engine/RunStatus.h), and the conversions the module shares: a JSON
// document and comparison.csv's typed table as Python objects.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "Bindings.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/engine/SummaryJson.h"

namespace py = pybind11;

namespace budget_slam::python {

py::object toPython(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

py::list comparisonTable(const std::vector<report::ComparisonRow>& rows) {
  py::list table;
  for (const auto& column : report::comparisonColumns()) {
    std::vector<report::ComparisonCell> cells;
    for (const auto& row : rows) cells.push_back(column.value(row));
    const report::ComparisonCell kind = column.value(report::ComparisonRow{});
    const bool text = kind.is_text;
    const bool integer = kind.is_integer && std::all_of(cells.begin(), cells.end(), [](auto& c) {
                           return std::isfinite(c.number);
                         });
    py::list values;
    for (const auto& c : cells) {
      if (text)
        values.append(c.text);
      else if (integer)
        values.append(static_cast<long long>(c.number));
      else
        values.append(c.number);
    }
    table.append(py::make_tuple(column.name,
                                text      ? "text"
                                : integer ? "integer"
                                          : "number",
                                values));
  }
  return table;
}

namespace {

/// runs::readSummary for Python: the document, and the outcome's typed fields.
py::dict readSummary(const std::string& path) {
  const runs::SummaryFile f = runs::readSummary(path);
  py::dict d;
  d["json"] = toPython(f.json);
  d["status"] = f.status_text;
  d["ok"] = f.outcome.ok();
  d["error"] = f.outcome.error;
  d["exit_code"] = runs::exitCode(f.outcome);
  return d;
}

/// runs::exitCode by the words summary.json and errorKindName use.
int exitCodeOf(const std::string& status, const std::string& kind) {
  const auto s = runs::parseStatus(status);
  if (!s) throw ConfigError("status '" + status + "': none of ok, failed, interrupted, not_found");
  for (const auto k : {runs::ErrorKind::None, runs::ErrorKind::CommandLine, runs::ErrorKind::Config,
                       runs::ErrorKind::Input, runs::ErrorKind::Diverged, runs::ErrorKind::Output,
                       runs::ErrorKind::Stopped, runs::ErrorKind::Internal})
    if (kind == runs::errorKindName(k)) return runs::exitCode(*s, k);
  throw ConfigError("error kind '" + kind + "': not one of the run layer's kinds");
}

}  // namespace

void defineOutcomeBindings(py::module_& m) {
  m.def("read_summary", &readSummary, py::arg("path"),
        "Reads a summary.json through the run layer's one reader (bounded; a bad file raises "
        "Error naming it). Returns a dict: json (the document), status, ok, error, exit_code.");
  m.def(
      "summary_keys", [] { return runs::summaryKeys(); },
      "summary.json's top-level keys the run layer writes (the others are what the command "
      "was given).");
  m.def("exit_code", &exitCodeOf, py::arg("status"), py::arg("kind") = "none",
        "The exit code of a command that ended `status` (ok, failed, interrupted) with error "
        "`kind` (none, command_line, config, input, diverged, output, stopped, internal).");
}

}  // namespace budget_slam::python
