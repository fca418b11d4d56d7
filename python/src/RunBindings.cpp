// run_request and localize: budget-slam's run, compare and localize in this process, through the
// run layer (runs::run, runs::compare, runs::localize) with a typed request, their outcome typed
// and in memory (docs/PYTHON.md).
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "Bindings.h"
#include "RequestArgs.h"
#include "RunGuard.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/RegistryListing.h"  // kVersion
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/Localize.h"

namespace py = pybind11;

namespace budget_slam::python {
namespace {

/// How a run() or compare() ended, typed: its exit code (runs::exitCode), status and error kind
/// (summary.json's words), the one line of a command that did not end ok (as the command line
/// prints it on stderr, without "budget-slam: " and "error: "), and its warnings in order.
struct CommandOutcome {
  int exit_code = 0;
  std::string status, kind;
  std::string message;
  std::vector<std::string> warnings;
  /// The outcome summary.json was written from (runs::summaryJson), in memory: what the run
  /// reported, not a file read back.
  nlohmann::json summary;
  /// compare: comparison.csv's rows (CompareReport::rows), and each run's name and the outcome
  /// its summary.json was written from (null when it could not be finished), in the rows' order.
  std::vector<report::ComparisonRow> rows;
  std::vector<std::pair<std::string, nlohmann::json>> runs;
};

/// `budget-slam run` or `compare` (command) in this process, through runs::run and
/// runs::compare. `params`: the ini text (in-memory config), else request["config"] is read as
/// the -c file. A refused request raises ConfigError with the command line's message.
CommandOutcome runRequest(const std::string& command, const py::dict& request_args,
                          const std::optional<std::string>& params,
                          const std::optional<py::function>& progress) {
  if (command != "run" && command != "compare")
    throw UsageError("unknown command '" + command + "' (expected run or compare)");
  runs::RequestContext context;
  // The same text checks as a -c file (core/IniText.h): a bad value is a ConfigError, never an
  // abort inside MRPT's variable expansion.
  if (params) loadIniText(context.params, *params, "config");
  const bool run = command == "run";
  std::optional<runs::RunRequest> run_request;
  std::optional<runs::CompareRequest> compare_request;
  if (run)
    run_request = runRequestOf(request_args);
  else
    compare_request = compareRequestOf(request_args);
  const std::string& config = run ? run_request->common.config : compare_request->common.config;
  if (!params) {
    context.config_label = config.empty() ? "config.ini" : config;
    context.config_text =
        readIniFile(context.config_label, "config file '" + context.config_label + "'");
  }
  context.writer = std::string("budget-slam ") + runs::kVersion;

  CommandOutcome r;
  runs::RunHooks hooks;
  hooks.warning = [&](const std::string& line) { r.warnings.push_back(line); };
  runGuarded(progress, hooks, [&] {
    runs::RunStatus status;
    runs::ErrorKind kind;
    if (run) {
      const runs::RunReport report = runs::run(*run_request, std::move(context), hooks);
      status = report.outcome.status, kind = report.outcome.kind;
      r.summary = runs::summaryJson(report.outcome);
      r.message = printable(report.line);
    } else {
      const runs::CompareReport report = runs::compare(*compare_request, std::move(context), hooks);
      status = report.outcome.status, kind = report.outcome.kind;
      r.summary = runs::summaryJson(report.summary);
      r.rows = report.rows;
      for (const auto& run : report.runs)
        r.runs.emplace_back(run.name, run.summary ? runs::summaryJson(*run.summary) : nullptr);
      // The comparison's last error or interruption says it; its warnings are warnings.
      for (const auto& line : report.outcome.lines) {
        if (line.kind == runs::CompareLine::Kind::Warning)
          r.warnings.push_back(printable(line.text));
        else
          r.message = printable(line.text);
      }
    }
    r.exit_code = runs::exitCode(status, kind);
    r.status = runs::statusName(status);
    r.kind = runs::errorKindName(kind);
  });
  return r;
}

/// runs::localize for Python (budget_slam.localize): the typed specification filled from the
/// arguments, no command line. The checks the command line makes before anything runs raise
/// ConfigError with its text (localizeRequestOf; a -c that cannot be read; an in-memory ini that
/// fails the text checks); whatever happens after is in the returned dict: status, kind,
/// exit_code, line (the one line, "" when ok), warnings, folder.
py::dict localizeRun(const std::optional<std::string>& config,
                     const std::optional<std::string>& params,
                     const std::optional<std::string>& rawlog, const std::string& map,
                     const std::string& outdir, const std::vector<std::string>& sets,
                     const std::optional<std::string>& start_pose, bool wake_up,
                     const std::optional<std::string>& reference_trajectory,
                     const std::optional<std::string>& max_steps, bool force,
                     const std::optional<py::function>& progress) {
  runs::LocalizeRequest r = localizeRequestOf(config, rawlog, map, outdir, sets, start_pose,
                                              wake_up, reference_trajectory, max_steps, force);
  runs::RequestContext context;
  if (config) {
    // As the command line reads -c: missing, a folder or over 1 MiB is a ConfigError here.
    context.config_text = readIniFile(*config, "config file '" + *config + "'");
    context.config_label = *config;
  } else if (params) {
    loadIniText(context.params, *params, "config");
  }

  runs::RunHooks hooks;
  runs::LocalizeReport result;
  runGuarded(progress, hooks, [&] { result = runs::localize(r, std::move(context), hooks); });
  py::dict d;
  d["status"] = runs::statusName(result.outcome.status);
  d["kind"] = runs::errorKindName(result.outcome.kind);
  d["exit_code"] = runs::exitCode(result.outcome);
  d["line"] = result.line;
  d["warnings"] = result.warnings;
  d["folder"] = result.folder;
  d["summary"] = toPython(runs::summaryJson(result.outcome));  // in memory, not read back
  return d;
}

}  // namespace

void defineRunBindings(py::module_& m) {
  py::class_<CommandOutcome>(m, "CommandOutcome")
      .def_property_readonly("summary", [](const CommandOutcome& o) { return toPython(o.summary); })
      .def_readonly("exit_code", &CommandOutcome::exit_code)
      .def_readonly("status", &CommandOutcome::status)
      .def_readonly("kind", &CommandOutcome::kind)
      .def_readonly("message", &CommandOutcome::message)
      .def_readonly("warnings", &CommandOutcome::warnings)
      .def_property_readonly("comparison",
                             [](const CommandOutcome& o) { return comparisonTable(o.rows); })
      .def_property_readonly("runs", [](const CommandOutcome& o) {
        py::list runs;
        for (const auto& [name, summary] : o.runs)
          runs.append(py::make_tuple(name, toPython(summary)));
        return runs;
      });
  m.def("run_request", &runRequest, py::arg("command"), py::arg("request"),
        py::arg("params") = py::none(), py::arg("progress") = py::none(),
        "Runs `run` or `compare` in this process through the run layer (runs::run, "
        "runs::compare) from a request dict (config, rawlog, outdir, force, reducer, reducers, "
        "backend, cap, sets, seeds, max_steps, skip_steps, threads, resume, wake_up); params: "
        "in-memory ini text; progress: called with a dict of how far it has come. Returns "
        "exit_code, status, kind, message, warnings, summary, and for compare comparison "
        "(comparison.csv's columns: name, kind, values) and runs ((name, summary) a run); raises "
        "ConfigError when the request is refused, and what the progress callback raised.");
  m.def("localize", &localizeRun, py::arg("config"), py::arg("params"), py::arg("rawlog"),
        py::arg("map"), py::arg("outdir"), py::arg("sets"), py::arg("start_pose"),
        py::arg("wake_up"), py::arg("reference_trajectory"), py::arg("max_steps"), py::arg("force"),
        py::arg("progress") = py::none(),
        "runs::localize with a typed specification (budget_slam.localize builds the arguments). "
        "Returns a dict: status, kind, exit_code, line, warnings, folder, summary; raises "
        "ConfigError for what the command line refuses before running, and what the progress "
        "callback raised.");
}

}  // namespace budget_slam::python
