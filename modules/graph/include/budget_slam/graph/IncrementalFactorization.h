#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/Solver.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// How the held factor keeps L (IncrementalFactorization's construction parameters).
struct HeldFactorParams {
  /// A fresh fill-reducing ordering once nnz(L) or the factorization flops per row exceed this
  /// many times their value after the last fresh ordering. <= 1: a fresh ordering and a full
  /// factorization at every change (nothing in place: the batch path).
  double reorder_fill_ratio = 1.5;
};

/// Gauss-Newton iterations on the held factor (IncrementalFactorization::iterate): the update
/// parameters.
struct IncrementalStep {
  int max_iterations = 2;
  /// A variable's factors are relinearized, at the start of an iteration, once its estimate has
  /// left their linearization point by more than this (max |dx| over its parameters, m and rad
  /// alike). 0: every variable that moved (full Gauss-Newton, with its divergence check).
  double relinearize_threshold = 0;
  /// Partial back-substitution (iSAM2's wildfire threshold): the solution is solved again in
  /// the rows the change re-eliminated, and in a row above them only when a row it depends on
  /// moved by more than this since (m and rad alike). 0: every change spreads (the solution
  /// equals a whole solve to rounding).
  double wildfire_threshold = 0;
  /// Converged when the estimate moves by less than this (max |dx|).
  double step_tolerance = 1e-10;
  /// ...or, with threshold 0, when chi2 drops by less than this fraction (0: off).
  double relative_chi2_tolerance = 0;
  /// Poll budget_slam::Cancellation before every iteration (a full solve takes seconds).
  bool stop_on_request = false;
};

/// What the held factor did so far (reports and benchmarks).
struct IncrementalStats {
  std::size_t rebuilds = 0;         ///< numeric refactorizations of L (fresh orderings included)
  std::size_t fresh_orderings = 0;  ///< rebuilds with a fresh fill-reducing ordering
  std::size_t modifications = 0;    ///< changes folded into L in place (each a batch of them)
  std::size_t folded_factors = 0;   ///< factors added, removed or relinearized in place
  std::size_t moved_variables = 0;  ///< variables relinearized in iterate() (past the threshold)
  /// Partial re-eliminations: L's rows from the first changed one on computed again, the rows
  /// above kept (included in `rebuilds`).
  std::size_t partial_refactorizations = 0;
  double partial_rows = 0;     ///< rows re-eliminated by them in all
  double partial_of_rows = 0;  ///< rows of the factors they re-eliminated, in all
  std::size_t solves = 0;      ///< solutions in iterate() (partial back-substitutions)
  double solved_rows = 0;      ///< rows of the solution they solved again, in all
  double solve_of_rows = 0;    ///< rows of the factors they solved, in all
};

/// What the last change folded into the held factor did, recorded by its named steps (the
/// journal read, rows retired and placed, H extended, L brought to H); a sync() with nothing to
/// fold in leaves it as it was.
struct HeldUpdate {
  /// How L was brought to H.
  enum class Fold : std::uint8_t {
    None,           ///< nothing changed
    InPlace,        ///< rank updates, row deletions and downdates (CHOLMOD's updown, rowdel)
    Refactorized,   ///< a numeric refactorization in the kept order
    Partial,        ///< only L's rows from the first changed one on re-eliminated
    FreshOrdering,  ///< a fresh fill-reducing ordering, H rebuilt and factorized
  };
  bool restarted = false;  ///< the graph was read afresh (first time, or journal out of reach)
  std::size_t new_variables = 0;
  std::size_t removed_variables = 0;
  std::size_t added_factors = 0;
  std::size_t removed_factors = 0;  ///< downdated out of H (not those added and removed)
  std::size_t relinearized_variables = 0;
  std::size_t relinearized_factors = 0;
  bool pattern_rebuilt = false;  ///< a new factor tied two variables H had no entry for
  int first_changed_row = -1;    ///< the first row of H the change touched (-1: none)
  Fold fold = Fold::None;
};

/// The Cholesky factor L D L^T of the graph's information matrix H, held between updates and
/// changed where the graph changes (docs/GRAPH.md "Held factor"). H is held in elimination order
/// (every variable's rows are its positions), so CHOLMOD needs no permutation: new factors and
/// variables are folded in by rank updates (CHOLMOD's updown), removed ones by row deletions and
/// downdates, and a Gauss-Newton step relinearizes only the variables whose estimate has moved
/// past the relinearization threshold (a downdate of their factors' old rows, an update with the
/// new ones). When a change would cost more in place than a numeric refactorization (a cost model
/// on the elimination-tree paths it touches), L is refactorized from the held H in the kept
/// order; when the fill has grown past `reorder_fill_ratio` times that of the last fresh ordering,
/// or the spare rows for new variables ran out, it is rebuilt with a fresh fill-reducing ordering.
///
/// The estimate is the linearization point plus the minimizer of the held linear model (iSAM2):
/// every variable takes every step; each keeps its linearization point until its estimate moves
/// past the threshold. So the factor is H at the linearization point; factor(graph, true) brings
/// it to the estimate first.
///
/// It follows one FactorGraph through its change journal (FactorGraph::changesSince); a copy
/// follows a copy of that graph after adopt().
///
/// Invariants between public calls (the implementation's parts hold them: HeldRecords,
/// HeldMatrix, HeldCholesky in src/; test_incremental.cpp checks them against batch solves):
/// 1. Each held variable's rows of H are its positions in the elimination order (P = I), rows
///    past the last placed variable are spare, and spare or removed rows are identity rows.
/// 2. H = sum over the held factors of A^T A at their variables' linearization points, g = sum
///    A^T r, chi2 = sum |r|^2 (a factor's linearization changes only with its variables').
/// 3. L D L^T = H to rounding (after every sync; L may hold explicit zeros after downdates
///    and row deletions until the next query at the estimate cuts them).
/// 4. The estimate = linearization point + the last step's minimizer (HeldSolution: exactly
///    with wildfire threshold 0; otherwise a row whose inputs moved less than the threshold
///    keeps its last value); each variable's estimate is within the relinearization threshold
///    of its linearization point, or it is relinearized at the next iteration.
/// 5. The held records are those of the graph at (lineage, changeCount, valuesVersion): a
///    change since is folded in by the next sync, or the graph is read afresh.
class IncrementalFactorization {
 public:
  explicit IncrementalFactorization(const HeldFactorParams& params = {});
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
  /// Gauss-Newton on the held factor from `graph`'s estimate: per iteration the variables past
  /// the threshold are relinearized, then estimate = linearization point + the minimizer of the
  /// linear model (solved again only where it changed: `wildfire_threshold`), written into
  /// `graph`. Stops when the estimate moves by less than
  /// step_tolerance, at max_iterations, or (threshold 0) when a step raised chi2 beyond rounding
  /// (the step is undone).
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
  /// What the last change folded in did (sync, or a relinearization in iterate()).
  const HeldUpdate& lastUpdate() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace budget_slam::graph
