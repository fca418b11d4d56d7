#include "budget_slam/graph/Solver.h"

#include <cmath>
#include <stdexcept>

#include "budget_slam/core/Cancellation.h"

namespace budget_slam::graph {

namespace {
bool factorizeWith(const FactorGraph& graph, const Eigen::SparseMatrix<double>& H,
                   SparseCholesky* chol) {
  // 0 means "always analyse"
  return chol->factorize(H, graph.structureVersion() + 1, &graph.variableStarts());
}
}  // namespace

void factorizeAtEstimate(const FactorGraph& graph, SparseCholesky* chol) {
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd g;
  graph.linearize(&H, &g);
  if (!factorizeWith(graph, H, chol))
    throw std::runtime_error("graph: information matrix is not positive definite");
}

SolveReport optimize(FactorGraph& graph, const SolverSettings& s, SparseCholesky* chol) {
  SolveReport rep;
  if (graph.dim() == 0) {
    rep.initial_chi2 = rep.final_chi2 = graph.chi2();
    rep.converged = true;
    return rep;
  }
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd g;
  double lambda = s.lm_initial_lambda;
  double chi2 = 0;
  if (s.max_iterations <= 0) rep.initial_chi2 = rep.final_chi2 = chi2 = graph.chi2();
  for (int it = 0; it < s.max_iterations; ++it) {
    if (s.stop_on_request) Cancellation::check();
    if (it == 0) {
      // The starting cost comes with the first linearization (same residuals); later ones are
      // known from the accepted step's evaluation.
      graph.linearize(&H, &g, &chi2);
      rep.initial_chi2 = rep.final_chi2 = chi2;
    } else {
      graph.linearize(&H, &g);
    }
    rep.iterations = it + 1;
    if (s.method == SolverSettings::Method::GaussNewton) {
      if (!factorizeWith(graph, H, chol))
        throw std::runtime_error("graph: information matrix is not positive definite");
      const Eigen::VectorXd dx = -chol->solve(g);
      const Eigen::VectorXd backup = graph.values();
      graph.retract(dx);
      const double new_chi2 = graph.chi2();
      if (new_chi2 > chi2 * (1 + 1e-9)) {
        // A Gauss-Newton step that raises the cost beyond rounding: diverging, far from the
        // optimum (use levenberg-marquardt there). Keep the better estimate and stop.
        graph.setValues(backup);
        break;
      }
      rep.last_step_norm = dx.lpNorm<Eigen::Infinity>();
      const bool small =
          rep.last_step_norm < s.step_tolerance ||
          (s.relative_chi2_tolerance > 0 && chi2 - new_chi2 <= s.relative_chi2_tolerance * chi2);
      chi2 = new_chi2;
      if (small) {
        rep.converged = true;
        break;
      }
      continue;
    }
    // Levenberg-Marquardt: (H + lambda diag(H)) dx = -g, accept if chi2 drops.
    const Eigen::VectorXd diag = H.diagonal();
    bool accepted = false;
    for (int tries = 0; tries < 20 && !accepted; ++tries) {
      if (s.stop_on_request) Cancellation::check();
      Eigen::SparseMatrix<double> Hd = H;
      for (int i = 0; i < Hd.rows(); ++i) Hd.coeffRef(i, i) += lambda * std::max(diag[i], 1e-12);
      if (!factorizeWith(graph, Hd, chol)) {
        lambda *= s.lm_lambda_factor;
        continue;
      }
      const Eigen::VectorXd dx = -chol->solve(g);
      const Eigen::VectorXd backup = graph.values();
      graph.retract(dx);
      const double new_chi2 = graph.chi2();
      if (new_chi2 <= chi2) {
        accepted = true;
        rep.last_step_norm = dx.lpNorm<Eigen::Infinity>();
        const bool small = rep.last_step_norm < s.step_tolerance ||
                           chi2 - new_chi2 <= s.relative_chi2_tolerance * chi2;
        chi2 = new_chi2;
        lambda = std::max(lambda / s.lm_lambda_factor, 1e-12);
        if (small) rep.converged = true;
      } else {
        graph.setValues(backup);
        lambda *= s.lm_lambda_factor;
      }
    }
    if (!accepted) {  // no descent left at machine precision: at the optimum
      rep.converged = true;
      break;
    }
    if (rep.converged) break;
  }
  rep.final_chi2 = chi2;
  return rep;
}

}  // namespace budget_slam::graph
