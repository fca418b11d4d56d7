// reducer_scores: what a registered reducer (built in or a Python plugin) makes of a Gaussian
// state given as numpy arrays, checked as a run checks its state and its configuration.
#include <mrpt/config/CConfigFileMemory.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "Bindings.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSchema.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/gaussian/GaussianStateBackend.h"
#include "budget_slam/reducers/BuiltinReducers.h"

namespace py = pybind11;

namespace budget_slam::python {
namespace {

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

}  // namespace

void defineReducerScores(py::module_& m) {
  m.def("reducer_scores", &reducerScores, py::arg("name"), py::arg("mean"), py::arg("cov"),
        py::arg("ids"), py::arg("n_obs") = py::none(), py::arg("obs_mean") = py::none(),
        py::arg("first_step") = py::none(), py::arg("last_step") = py::none(), py::arg("step") = 0,
        py::arg("seed") = 1, py::arg("config") = "", py::arg("candidates") = py::none());
}

}  // namespace budget_slam::python
