#pragma once
// What a plugin reducer's calls are given (docs/PYTHON.md "A reducer in Python"): the Drop of
// choose(drop) and the Seen of observe(seen), and their Python bindings.
#include <pybind11/pybind11.h>

#include <optional>

#include "budget_slam/core/Reducer.h"

namespace budget_slam::python {

/// What a plugin's choose() gets: the decision's step and candidates, every landmark of the map,
/// and the backend's estimates on request. Owned by Python; it points into the budget manager's
/// frame during the call only, then expires (a Drop kept past its call raises RuntimeError).
class DropView {
 public:
  DropView(const DropContext& ctx, std::uint64_t seed) : ctx_(&ctx), seed_(seed) {}
  void expire() { ctx_ = nullptr; }

  const DropContext& ctx() const;
  std::uint64_t seed() const { return seed_; }
  /// The candidates' columns (id, x, y, var_x, var_y, cov_xy, n_obs, obs_x, obs_y, first_step,
  /// last_step), made at the first access.
  pybind11::dict candidates();
  /// Every landmark's columns, plus `candidate`.
  pybind11::dict landmarks();

 private:
  const DropContext* ctx_;
  std::uint64_t seed_;
  std::optional<pybind11::dict> candidates_, landmarks_;
};

/// What a plugin's observe() gets at every step (core/Reducer.h StepObservation), a copy.
struct SeenView {
  StepObservation seen;
};

/// Defines the classes Drop and Seen in `m`.
void definePluginViews(pybind11::module_& m);

}  // namespace budget_slam::python
