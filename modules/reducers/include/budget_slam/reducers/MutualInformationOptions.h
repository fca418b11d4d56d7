#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::reducers {

/// [MutualInformationReducer]: the `mi` reducer (Choudhary et al. ICRA 2015; docs/ALGORITHMS.md
/// "mi").
struct MutualInformationOptions : public TabledOptions<MutualInformationOptions> {
  static constexpr const char* kSection = "MutualInformationReducer";

  /// When landmarks go:
  ///  cap:         only when the map is over [LandmarkBudget] max_landmarks, least informative
  ///               first (Alg. 4 as a victim picker).
  ///  objective:   additionally Alg. 3 (active minimization) once, after the last step.
  ///  incremental: additionally Alg. 3 every `psi` steps (Alg. 5); dropped landmarks never return.
  enum class Mode { Cap, Objective, Incremental };
  Mode mode = Mode::Cap;
  double lambda = 0.4;    ///< weight of memory vs. accuracy in rho, Eq. 4, in [0, 1] (paper: 0.4)
  std::size_t psi = 500;  ///< Psi: steps between two minimizations in incremental mode, >= 1
  std::size_t pose_lag = 5;  ///< P: landmarks seen in the last P steps are no Alg. 3 candidates,
                             ///< and the last P poses are never marginalized [steps]
  /// Where Alg. 3 stops along the greedy sequence:
  ///  first_increase: at the first rho_k > rho_{k-1} (Alg. 3 line 9, as printed; default).
  ///  global_minimum: at the smallest rho over the whole sequence (Sec. IV-C, Fig. 3).
  enum class Stop { FirstIncrease, GlobalMinimum };
  Stop stop = Stop::FirstIncrease;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<MutualInformationOptions>& table();
  static std::string modeName(Mode m);
  static std::string stopName(Stop s);
};

}  // namespace budget_slam::reducers
