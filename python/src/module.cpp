// budget_slam._core: the C++ half of the budget_slam Python module (python/budget_slam/__init__.py
// is the other). It runs `run` and `compare` in-process through the run layer (runs::run,
// runs::compare, with a typed request) and scores Gaussian states with the registered reducers;
// reading the run's files into numpy arrays is left to the Python half.
#include <mrpt/config/CConfigFileMemory.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <optional>
#include <set>
#include <type_traits>

#include "CoreModule.h"
#include "PythonReducer.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSchema.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/RegistryListing.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/gaussian/GaussianStateBackend.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/Figure.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/RequestChecks.h"

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
};

/// A progress report as the dict Python's progress= callback receives (docs/PYTHON.md).
py::dict progressDict(const ProgressSnapshot& s) {
  py::dict d;
  d["task"] = s.task;
  d["fraction"] = s.fraction;
  d["steps_done"] = s.steps_done;
  d["steps_total"] = s.steps_total ? py::object(py::int_(s.steps_total)) : py::object(py::none());
  d["elapsed_s"] = s.elapsed_s;
  d["steps_per_s"] = s.steps_per_s;
  d["eta_s"] = s.eta_s;
  d["detail"] = s.detail;
  d["finished"] = s.finished;
  return d;
}

/// Python's progress= as a ProgressCallback (none without one). It runs on the calling thread
/// with the GIL taken back; an exception it raises is kept in `error` and stops the run as Ctrl-C
/// does (every output written), to be raised again once the run has ended.
ProgressCallback progressCallback(const std::optional<py::function>& progress,
                                  std::optional<py::error_already_set>& error) {
  if (!progress) return {};
  return [progress, &error](const ProgressSnapshot& s) {
    if (error) return;
    py::gil_scoped_acquire gil;
    try {
      (*progress)(progressDict(s));
    } catch (py::error_already_set& e) {
      error.emplace(std::move(e));
      Cancellation::request(SIGINT);
    }
  };
}

/// Runs `call` (one of the run layer's commands) as the command line would: the GIL released
/// (Ctrl-C then reaches the stop request's handler), the stop signals' handlers installed for the
/// call and a stop request left by an earlier call cleared (as BudgetSlamApp::run), the figure
/// fonts loaded while descriptors are to be had (report/Figure.h), and `progress` as the hooks'
/// callback. What the callback raised is raised again once the call has ended.
template <class Call>
void runGuarded(const std::optional<py::function>& progress, runs::RunHooks& hooks,
                const Call& call) {
  std::optional<py::error_already_set> callback_error;
  hooks.progress.callback = progressCallback(progress, callback_error);
  {
    py::gil_scoped_release release;
    const bool first_guard = !StopSignals::installed();
    StopSignals signals;
    if (first_guard) Cancellation::clear();
    report::loadFigureFonts();
    call();
  }
  if (callback_error) {
    callback_error->restore();
    throw py::error_already_set();
  }
}

/// The typed request of run() (runs::RunRequest) or compare() (runs::CompareRequest) from their
/// arguments (python/budget_slam/__init__.py _invoke): the same checks, in the same order and
/// with the same messages, as the command line's (BudgetSlamApp::initialize). A refused value
/// raises ConfigError.
template <class Request>
Request requestOf(const std::string& command, const py::dict& d) {
  constexpr bool kRun = std::is_same_v<Request, runs::RunRequest>;
  const auto text = [&](const char* key) {
    return d.contains(key) && !d[key].is_none()
               ? std::optional<std::string>(py::str(d[key]).cast<std::string>())
               : std::nullopt;
  };
  Request r;
  r.common.config = text("config").value_or("");
  r.common.rawlog = text("rawlog").value_or("");
  r.common.outdir = text("outdir").value_or("");
  r.common.quiet = true;  // nothing on stdout, no progress on stderr: the callback has it
  r.common.force = d.contains("force") && d["force"].cast<bool>();
  if (d.contains("sets")) r.common.sets = d["sets"].cast<std::vector<std::string>>();
  r.backend = text("backend").value_or("");
  std::optional<std::string> reducers;
  if constexpr (kRun) {
    r.reducer = text("reducer").value_or("");
    r.resume = text("resume").value_or("");
    r.wake_up = d.contains("wake_up") && d["wake_up"].cast<bool>();
    runs::checkWakeUp(r);
  } else {
    if (d.contains("reducers") && !d["reducers"].is_none()) {
      std::string joined;
      for (const auto& n : d["reducers"].cast<std::vector<std::string>>()) {
        joined += (joined.empty() ? "" : ",") + n;
        if (!n.empty()) r.reducers.push_back(n);
      }
      reducers = joined;
    }
    if (d.contains("threads")) r.threads = static_cast<unsigned>(d["threads"].cast<long long>());
  }
  try {
    // A flag given with an empty value (the command line's refuseEmptyValues, its order).
    const std::pair<const char*, std::optional<std::string>> given[] = {
        {"config", text("config")},   {"input", text("rawlog")},    {"out", text("outdir")},
        {"reducer", text("reducer")}, {"reducers", reducers},       {"seeds", text("seeds")},
        {"cap", text("cap")},         {"backend", text("backend")}, {"resume", text("resume")}};
    for (const auto& [flag, value] : given) runs::refuseEmptyValue(flag, value);
    if (const auto v = text("max_steps")) r.common.max_steps = runs::parseMaxSteps(*v);
    if constexpr (kRun) {
      if (const auto v = text("skip_steps")) r.skip_steps = runs::parseSkipSteps(*v);
    } else {
      if (const auto v = text("seeds")) r.seeds = runs::parseSeeds(*v);
    }
    if (const auto v = text("cap")) r.cap = runs::parseCap(*v);
    runs::checkRequest(r);
  } catch (const ConfigError& e) {
    throw runs::withHelpHint(command, e);
  }
  return r;
}

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
    run_request = requestOf<runs::RunRequest>(command, request_args);
  else
    compare_request = requestOf<runs::CompareRequest>(command, request_args);
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

/// A JSON document as Python objects (through Python's json module: numbers, null, nesting as
/// json.load gives them).
py::object toPython(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// runs::localize for Python (budget_slam.localize): the typed specification filled from the
/// arguments, no command line. The checks the command line makes before anything runs raise
/// ConfigError with its text (a bad --start-pose, --wake-up with a start pose, an empty value, a
/// bad --max-steps, a -c that cannot be read; an in-memory ini that fails the text checks);
/// whatever happens after is in the returned dict: status, kind, exit_code, line (the one line,
/// "" when ok), warnings, folder.
py::dict localizeRun(const std::optional<std::string>& config,
                     const std::optional<std::string>& params,
                     const std::optional<std::string>& rawlog, const std::string& map,
                     const std::string& outdir, const std::vector<std::string>& sets,
                     const std::optional<std::string>& start_pose, bool wake_up,
                     const std::optional<std::string>& reference_trajectory,
                     const std::optional<std::string>& max_steps, bool force,
                     const std::optional<py::function>& progress) {
  runs::LocalizeRequest r;
  runs::RequestContext context;
  r.common.config = config.value_or("");
  r.map_dir = map;
  r.common.rawlog = rawlog.value_or("");
  r.common.outdir = outdir;
  r.common.sets = sets;
  r.start_pose = start_pose;
  r.wake_up = wake_up;
  r.reference_trajectory = reference_trajectory.value_or("");
  r.common.force = force;
  r.common.quiet = true;
  try {
    runs::checkRequest(r);
    // A value given empty is refused, as the command line refuses `--map ''`.
    for (const auto& [flag, value] :
         {std::pair<const char*, std::optional<std::string>>{"config", config},
          {"map", map},
          {"input", rawlog},
          {"out", outdir},
          {"reference-trajectory", reference_trajectory}})
      runs::refuseEmptyValue(flag, value);
    if (max_steps) r.common.max_steps = runs::parseMaxSteps(*max_steps);
  } catch (const ConfigError& e) {
    throw runs::withHelpHint("localize", e);
  }
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

Eigen::MatrixXd toMatrix(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                         const char* what) {
  if (a.ndim() != 2 || a.shape(0) != a.shape(1))
    throw ConfigError(std::string(what) + ": expected a square 2-D array");
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  auto v = a.unchecked<2>();
  for (py::ssize_t r = 0; r < a.shape(0); ++r)
    for (py::ssize_t c = 0; c < a.shape(1); ++c) m(r, c) = v(r, c);
  return m;
}

std::vector<double> toVector(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& a, const char* what) {
  if (a.ndim() != 1) throw ConfigError(std::string(what) + ": expected a 1-D array");
  return std::vector<double>(a.data(), a.data() + a.shape(0));
}

/// Scores of a Gaussian state (robot x, y, yaw, then x, y of each landmark, the layout of
/// states/step_<k>.txt) by reducer `name`: for each landmark the score the reducer gives it when
/// it is the only candidate, and the reducer's choice among `candidates` (default: all).
py::dict reducerScores(const std::string& name, const py::array_t<double>& mean_in,
                       const py::array_t<double>& cov_in, const std::vector<long long>& ids,
                       const std::optional<std::vector<long long>>& n_obs,
                       const std::optional<py::array_t<double>>& obs_mean,
                       const std::optional<std::vector<long long>>& first_step,
                       const std::optional<std::vector<long long>>& last_step, long long step,
                       std::uint64_t seed, const std::string& config,
                       const std::optional<std::vector<long long>>& candidates) {
  const auto& registry = reducers::builtinReducers();
  registry.entry(name);  // unknown name: ConfigError listing the registered ones
  // The reducers' sections only, each key known and each value in range, as a run checks them:
  // "x" or "[Foo] ..." is a mistake, not an empty configuration.
  mrpt::config::CConfigFileMemory ini;
  if (!config.empty()) {
    loadIniText(ini, config, "config");
    IniSchema schema;
    for (const auto* e : registry.entries())
      for (const auto& section : e->sections) schema.addSection(section.name, section.keys());
    try {
      schema.validate(ini);
      for (const auto* e : registry.entries()) e->validate(ini);
    } catch (const ConfigError& e) {
      throw ConfigError(std::string("config: ") + e.what());
    }
  }
  if (!registry.create(name, ini, seed))
    throw ConfigError("reducer '" + name + "' scores nothing: it is the unreduced run");

  const std::vector<double> mean = toVector(mean_in, "mean");
  const Eigen::MatrixXd P = toMatrix(cov_in, "cov");
  const std::size_t n = ids.size();
  if (mean.size() != 3 + 2 * n)
    throw ConfigError("mean: " + std::to_string(mean.size()) + " values, expected 3 + 2 x " +
                      std::to_string(n) + " ids = " + std::to_string(3 + 2 * n));
  if (static_cast<std::size_t>(P.rows()) != mean.size())
    throw ConfigError("cov: " + std::to_string(P.rows()) + " x " + std::to_string(P.cols()) +
                      ", expected " + std::to_string(mean.size()) + " square");
  if (!P.allFinite() ||
      !std::all_of(mean.begin(), mean.end(), [](double v) { return std::isfinite(v); }))
    throw ConfigError("mean, cov: values must be finite");
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, P.cwiseAbs().maxCoeff()))
    throw ConfigError("cov: not symmetric");
  // A covariance: a score of a matrix that is none (-I) would be a number that means nothing. A
  // filter's own state may be singular or off by round-off (a robot that has not moved, a
  // landmark seen once): an eigenvalue below -1e-6 of the largest is what no covariance has.
  if (P.rows() > 0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P, Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& l = eig.eigenvalues();
    if (eig.info() != Eigen::Success || l.minCoeff() < -1e-6 * l.cwiseAbs().maxCoeff())
      throw ConfigError("cov: not positive semi-definite (its least eigenvalue is " +
                        option::numberText(l.minCoeff()) + ")");
  }
  const auto sized = [n](const auto& v, const char* what) {
    if (v && v->size() != n)
      throw ConfigError(std::string(what) + ": " + std::to_string(v->size()) + " values for " +
                        std::to_string(n) + " ids");
  };
  sized(n_obs, "n_obs");
  sized(first_step, "first_step");
  sized(last_step, "last_step");
  std::vector<double> obs;
  if (obs_mean) {
    obs.assign(obs_mean->data(), obs_mean->data() + obs_mean->size());
    if (obs_mean->ndim() != 2 || obs.size() != 2 * n)
      throw ConfigError("obs_mean: expected an array of " + std::to_string(n) + " x 2");
  }

  std::vector<LandmarkView> landmarks(n);
  for (std::size_t i = 0; i < n; ++i) {
    LandmarkView& l = landmarks[i];
    l.id = static_cast<LandmarkId>(ids[i]);
    l.mean = {mean[3 + 2 * i], mean[4 + 2 * i]};
    // Without observation positions, each landmark counts as seen from where it is.
    l.obs_mean = obs_mean ? Eigen::Vector2d(obs[2 * i], obs[2 * i + 1]) : l.mean;
    if (n_obs) l.n_obs = static_cast<std::size_t>((*n_obs)[i]);
    if (first_step) l.first_step = static_cast<StepIndex>((*first_step)[i]);
    l.last_step = last_step ? static_cast<StepIndex>((*last_step)[i]) : l.first_step;
  }
  std::vector<std::size_t> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = i;
  std::vector<std::size_t> chosen_from = all;
  if (candidates) {
    chosen_from.clear();
    for (const long long c : *candidates) {
      const auto it = std::find(ids.begin(), ids.end(), c);
      if (it == ids.end())
        throw ConfigError("candidates: landmark " + std::to_string(c) + " is not among the ids");
      chosen_from.push_back(static_cast<std::size_t>(it - ids.begin()));
    }
  }
  if (n == 0 || chosen_from.empty()) throw ConfigError("no landmark to score");

  std::set<LandmarkId> unique;
  for (const auto& l : landmarks)
    if (!unique.insert(l.id).second)
      throw ConfigError("ids: landmark " + std::to_string(l.id) + " is listed twice");
  std::vector<double> s(n);
  ReducerChoice choice;
  {
    py::gil_scoped_release release;
    const gaussian::GaussianStateBackend backend(landmarks, P, static_cast<StepIndex>(step));
    const auto views = backend.landmarks();  // marginal covariances filled in from P
    const auto stepIndex = static_cast<StepIndex>(step);
    for (std::size_t i = 0; i < n; ++i) {
      // A fresh reducer a question: each answer depends only on the state (random: its seed).
      const std::vector<std::size_t> one = {i};
      s[i] = registry.create(name, ini, seed)->choose({backend, views, one, stepIndex}).score;
    }
    choice = registry.create(name, ini, seed)->choose({backend, views, chosen_from, stepIndex});
  }
  py::array_t<double> scores(static_cast<py::ssize_t>(n));
  py::array_t<long long> out_ids(static_cast<py::ssize_t>(n));
  auto sv = scores.mutable_unchecked<1>();
  auto iv = out_ids.mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) sv(i) = s[i], iv(i) = ids[i];
  py::dict d;
  d["ids"] = out_ids;
  d["scores"] = scores;
  d["choice"] = static_cast<long long>(choice.id);
  d["choice_score"] = choice.score;
  return d;
}

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
}  // namespace budget_slam::python

namespace budget_slam::python {

void defineCoreModule(py::module_& m) {
  m.doc() = "C++ core of budget_slam: the run layer in-process and the reducer registry";
  static py::exception<budget_slam::ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
  static py::exception<budget_slam::Error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const budget_slam::ConfigError& e) {
      config_error(e.what());
    } catch (const budget_slam::Error& e) {
      error(e.what());
    }
  });

  py::class_<CommandOutcome>(m, "CommandOutcome")
      .def_property_readonly("summary", [](const CommandOutcome& o) { return toPython(o.summary); })
      .def_readonly("exit_code", &CommandOutcome::exit_code)
      .def_readonly("status", &CommandOutcome::status)
      .def_readonly("kind", &CommandOutcome::kind)
      .def_readonly("message", &CommandOutcome::message)
      .def_readonly("warnings", &CommandOutcome::warnings);
  m.def("run_request", &runRequest, py::arg("command"), py::arg("request"),
        py::arg("params") = py::none(), py::arg("progress") = py::none(),
        "Runs `run` or `compare` in this process through the run layer (runs::run, "
        "runs::compare) from a request dict (config, rawlog, outdir, force, reducer, reducers, "
        "backend, cap, sets, seeds, max_steps, skip_steps, threads, resume, wake_up); params: "
        "in-memory ini text; progress: called with a dict of how far it has come. Returns "
        "exit_code, status, kind, message, warnings; raises ConfigError when the request is "
        "refused, and what the progress callback raised.");
  m.def("localize", &localizeRun, py::arg("config"), py::arg("params"), py::arg("rawlog"),
        py::arg("map"), py::arg("outdir"), py::arg("sets"), py::arg("start_pose"),
        py::arg("wake_up"), py::arg("reference_trajectory"), py::arg("max_steps"), py::arg("force"),
        py::arg("progress") = py::none(),
        "runs::localize with a typed specification (budget_slam.localize builds the arguments). "
        "Returns a dict: status, kind, exit_code, line, warnings, folder; raises ConfigError for "
        "what the command line refuses before running, and what the progress callback raised.");
  m.def("read_summary", &readSummary, py::arg("path"),
        "Reads a summary.json through the run layer's one reader (bounded; a bad file raises "
        "Error naming it). Returns a dict: json (the document), status, ok, error, exit_code.");
  m.def(
      "summary_keys", [] { return budget_slam::runs::summaryKeys(); },
      "summary.json's top-level keys the run layer writes (the others are what the command "
      "was given).");
  m.def("exit_code", &exitCodeOf, py::arg("status"), py::arg("kind") = "none",
        "The exit code of a command that ended `status` (ok, failed, interrupted) with error "
        "`kind` (none, command_line, config, input, diverged, output, stopped, internal).");
  m.def("reducer_names", [] { return budget_slam::reducers::builtinReducers().names(); });
  m.def("reducer_scores", &reducerScores, py::arg("name"), py::arg("mean"), py::arg("cov"),
        py::arg("ids"), py::arg("n_obs") = py::none(), py::arg("obs_mean") = py::none(),
        py::arg("first_step") = py::none(), py::arg("last_step") = py::none(), py::arg("step") = 0,
        py::arg("seed") = 1, py::arg("config") = "", py::arg("candidates") = py::none());
  m.def(
      "registry", [](const std::string& kind) { return toPython(runs::registryEntries(kind)); },
      py::arg("kind"),
      "The registered reducers or backends (kind: reducers, backends), each a dict: name, "
      "summary, options (section, key, default, doc); what budget-slam --list <kind> --json "
      "prints.");
  definePluginApi(m);  // register_reducer, Drop, Seen (PythonReducer.cpp)
}

}  // namespace budget_slam::python
