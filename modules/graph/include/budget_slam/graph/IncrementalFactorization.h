#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/Solver.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// Gauss-Newton iterations on the held factor (IncrementalFactorization::iterate).
struct IncrementalStep {
  int max_iterations = 2;
  /// A variable takes its step only when the step moves it by more than this (max |dx| over its
  /// parameters, m and rad alike); only the factors on variables that moved are relinearized.
  /// 0: every variable the step moves.
  double relinearize_threshold = 0;
  /// Converged when max |dx| falls below this (the step is then not taken).
  double step_tolerance = 1e-10;
  /// ...or when chi2 drops by less than this fraction (0: off).
  double relative_chi2_tolerance = 0;
  /// Poll budget_slam::Cancellation before every iteration (a full solve takes seconds).
  bool stop_on_request = false;
};

/// What the held factor did so far (reports and benchmarks).
struct IncrementalStats {
  std::size_t rebuilds = 0;         ///< every factor relinearized and H factorized anew
  std::size_t fresh_orderings = 0;  ///< rebuilds with a fresh fill-reducing ordering
  std::size_t modifications = 0;    ///< in-place changes of the factor (each a batch of them)
  std::size_t folded_factors = 0;   ///< factors added, removed or relinearized in place
  std::size_t moved_variables = 0;  ///< variables that took a step in iterate()
};

/// The Cholesky factor P H P^T = L D L^T of the graph's information matrix, held between updates
/// and changed where the graph changes (docs/GRAPH.md "Held factor"): new factors and variables
/// are folded in by rank updates (CHOLMOD's updown on the update permuted into the factor's
/// ordering), removed ones by row deletions and downdates, and a Gauss-Newton step moves only
/// the variables whose step exceeds the relinearization threshold, whose factors are then
/// relinearized by a downdate of their old rows and an update with the new ones. When that
/// would cost more than building the factor afresh (many factors at once, a full solve), every
/// factor is relinearized and H factorized again, with a fresh fill-reducing ordering when the
/// fill has grown past `reorder_fill_ratio` times the last fresh one or the spare rows for new
/// variables ran out.
///
/// Every variable's factors are linearized at its current value: the estimate is the
/// linearization point (a step below the threshold is not taken), so H here is H at the graph's
/// estimate, the matrix every covariance and information-gain query reads, and equals a fresh
/// factorization of it up to rounding (tests).
///
/// It follows one FactorGraph through its change journal (FactorGraph::changesSince); a copy
/// follows a copy of that graph after adopt().
class IncrementalFactorization {
 public:
  /// `reorder_fill_ratio` <= 1: a fresh ordering at every rebuild.
  explicit IncrementalFactorization(double reorder_fill_ratio = 1.5);
  /// A deep copy of the factor and everything it holds (CHOLMOD's copy of the factor).
  IncrementalFactorization(const IncrementalFactorization& other);
  IncrementalFactorization& operator=(const IncrementalFactorization&) = delete;
  ~IncrementalFactorization();

  /// This copy goes with `copy`, a copy of the graph the original followed, taken when the
  /// original was copied (GraphBackend::clone()).
  void adopt(const FactorGraph& copy);
  /// True when the held factor is that of `graph` as it stands now.
  bool isCurrent(const FactorGraph& graph) const;
  /// Folds every change of `graph` since the last call into the held factor: structure from the
  /// journal; values changed by anyone else relinearize their variables' factors.
  void sync(const FactorGraph& graph);
  /// The held factor (sync first), its queries addressed by `graph`'s columns
  /// (SparseCholesky::setColumnMap): H at the linearization point, within the relinearization
  /// threshold of the estimate and at most one Gauss-Newton step behind it. Throws
  /// std::runtime_error when H is not positive definite (an unconstrained variable).
  /// `at_estimate`: H at the estimate itself, for the queries that walk the elimination-tree paths
  /// of many variables (information gains, every landmark's marginal): every variable whose
  /// estimate left its linearization point is relinearized first (all of them after an update:
  /// one refactorization, then none until the estimate moves again); L's pattern is cut to H's
  /// after removals, and the factor takes a fresh ordering when its fill per row exceeds
  /// kQueryFillRatio times the last fresh one's (the paths' length grows with it).
  const SparseCholesky& factor(const FactorGraph& graph, bool at_estimate = false);
  static constexpr double kQueryFillRatio = 1.15;
  /// Gauss-Newton on the held factor from `graph`'s estimate: per iteration the step
  /// dx = -H^-1 g, taken by the variables it moves by more than the threshold, whose factors are
  /// relinearized. Stops at max |dx| < step_tolerance, when no variable moves, at
  /// max_iterations, or when a step raises chi2 beyond rounding (the step is undone).
  SolveReport iterate(FactorGraph& graph, const IncrementalStep& step);
  /// The minimizer of the linearized cost relative to the linearization point, dx = -H^-1 g,
  /// in `graph`'s column layout (sync first): the held factor's solution, which a batch solve
  /// from the same linearization (linearizationPoint()) must equal.
  Eigen::VectorXd step(const FactorGraph& graph);
  /// Every variable's linearization point in `graph`'s column layout (sync first): within the
  /// relinearization threshold of the estimate the graph holds, up to the last step.
  Eigen::VectorXd linearizationPoint(const FactorGraph& graph);
  /// Sum of squared whitened residuals at the estimate (kept with the factor).
  double chi2() const;
  const IncrementalStats& stats() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace budget_slam::graph
