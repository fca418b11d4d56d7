#include "budget_slam/graph/IncrementalFactorization.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "HeldCholesky.h"
#include "HeldMatrix.h"
#include "HeldRecords.h"
#include "HeldSolution.h"
#include "budget_slam/core/Cancellation.h"

namespace budget_slam::graph {

using held::Held;
using held::Piece;
using held::Var;

namespace {
/// Spare rows for new variables after a fresh ordering: a quarter of the used ones, at least
/// this many (64 poses).
constexpr int kMinSpareRows = 192;
/// A fresh ordering puts the variables touched by the last this many changes last (constrained
/// AMD, iSAM2's constrained COLAMD): the next changes touch them again, so the rows they
/// re-eliminate are few.
constexpr std::uint64_t kRecentChanges = 20;

/// The largest |difference| of two values of a variable of `dim` parameters, a pose's yaw
/// (the third) wrapped.
double maxAbsDifference(int dim, const double* a, const double* b) {
  double m = 0;
  for (int t = 0; t < dim; ++t) {
    const double d = t == 2 ? wrapAngle(a[t] - b[t]) : a[t] - b[t];
    m = std::max(m, std::abs(d));
  }
  return m;
}
}  // namespace

/// The held factor: its records, H, L, where it stands in the graph's journal, and the named
/// steps of an update (docs/GRAPH.md "Held factor"). Each step records into `last`.
struct IncrementalFactorization::State {
  explicit State(const HeldFactorParams& p) : params(p) {}

  HeldFactorParams params;
  held::HeldRecords rec;
  held::HeldMatrix H;
  held::HeldCholesky L;
  held::HeldSolution sol;  ///< dx = -H^-1 g, solved again only where it changed
  // Where the held records stand in the graph's journal (invariant 5).
  bool built = false;
  std::uint64_t lineage = 0, seq = 0, values_version = 0;
  IncrementalStats stats;
  HeldUpdate last;
  std::uint64_t change_count = 1;  ///< changes folded in so far (Var::touched)
  // Scratch of one change.
  std::vector<Piece> ups, downs;
  std::vector<int> deleted_rows, new_vars, new_factors, identity_rows;
  std::vector<unsigned> stamp, var_stamp;
  unsigned stamp_counter = 0, var_stamp_counter = 0;
  Eigen::VectorXd est_before;  ///< iterate(): the estimate before the last step

  bool batch() const { return params.reorder_fill_ratio <= 1; }

  // ---- reading the graph ----

  /// Every variable and factor of `graph` afresh (the first time, or when the journal no longer
  /// reaches back to the last change folded in).
  void readGraph(const FactorGraph& graph) {
    rec.read(graph);
    lineage = graph.lineage();
    seq = graph.changeCount();
    values_version = graph.valuesVersion();
    built = false;
    H.est.resize(0);  // the estimate is the graph's values: reorder() takes them from `lin`
    last = HeldUpdate();
    last.restarted = true;
  }

  // ---- bringing L to H ----

  /// A fresh fill-reducing ordering: AMD on the variable graph, postordered; the variables'
  /// rows renumbered in that order, spare rows after; H rebuilt and factorized (the factors keep
  /// their linearizations).
  void reorder() {
    std::vector<Var>& vars = rec.vars;
    std::vector<int> alive;
    for (int v = 0; v < static_cast<int>(vars.size()); ++v)
      if (vars[v].alive) alive.push_back(v);
    const int nv = static_cast<int>(alive.size());
    std::vector<int> node(vars.size(), -1);
    for (int k = 0; k < nv; ++k) node[alive[k]] = k;
    // Strict upper triangle of the variable graph.
    std::vector<std::vector<int>> adj(static_cast<std::size_t>(nv));
    for (const Held& h : rec.factors)
      if (h.alive && h.var[1] >= 0) {
        const int a = node[h.var[0]], b = node[h.var[1]];
        if (a != b) adj[std::max(a, b)].push_back(std::min(a, b));
      }
    std::vector<int> p(static_cast<std::size_t>(nv) + 1, 0), i;
    for (int c = 0; c < nv; ++c) {
      std::sort(adj[c].begin(), adj[c].end());
      adj[c].erase(std::unique(adj[c].begin(), adj[c].end()), adj[c].end());
      i.insert(i.end(), adj[c].begin(), adj[c].end());
      p[c + 1] = static_cast<int>(i.size());
    }
    // The variables touched by the last changes last (not on the batch path: plain AMD).
    std::vector<int> group;
    if (!batch()) {
      group.assign(static_cast<std::size_t>(nv), 0);
      for (int k = 0; k < nv; ++k)
        if (vars[alive[k]].touched + kRecentChanges >= change_count) group[k] = 1;
    }
    const std::vector<int> order = L.chol.orderNodes(nv, p, i, group.empty() ? nullptr : &group);
    // The estimate moves with its variables (it is the linearization point plus the last step).
    std::vector<Eigen::Vector3d> estimate(static_cast<std::size_t>(nv));
    for (int k = 0; k < nv; ++k) {
      const Var& r = vars[alive[k]];
      estimate[k] = r.lin;
      if (r.row >= 0 && r.row + r.dim <= H.est.size())
        estimate[k].head(r.dim) = H.est.segment(r.row, r.dim);
    }
    int row = 0;
    for (int k : order) {
      Var& r = vars[alive[k]];
      r.row = row;
      row += r.dim;
    }
    H.next_row = row;
    H.owner.assign(static_cast<std::size_t>(row + std::max(kMinSpareRows, row / 4)), -1);
    H.est.setZero(H.capacity());
    for (int k = 0; k < nv; ++k) {
      Var& r = vars[alive[k]];
      for (int t = 0; t < r.dim; ++t) H.owner[r.row + t] = alive[k];
      H.est.segment(r.row, r.dim) = estimate[k].head(r.dim);
    }
    H.dead_rows = 0;
    H.buildPattern(rec);
    L.chol.setColumnMap({});
    L.map_valid = false;
    sol.invalidate();
    built = false;
    if (!L.chol.factorizeInOrder(H.upper()))
      throw std::runtime_error("graph: information matrix is not positive definite");
    built = true;
    L.stale_pattern = false;
    L.refresh_flops = L.chol.analysedFlops();
    L.fresh_fill = L.nonZerosOfL() / std::max(1, H.next_row);
    L.fresh_flops = L.refresh_flops / std::max(1, H.next_row);
    L.fresh_depth = L.meanDepth(H.owner);
    L.computePathCosts();
    ++stats.rebuilds;
    ++stats.fresh_orderings;
    last.fold = HeldUpdate::Fold::FreshOrdering;
  }

  /// L from H by a numeric refactorization in the kept order and storage.
  void refresh() {
    sol.invalidate();
    if (!L.chol.refactorizeInOrder(H.upper())) {
      built = false;
      throw std::runtime_error("graph: information matrix is not positive definite");
    }
    L.refresh_flops = L.chol.lastFactorizationFlops();
    L.stale_pattern = false;
    L.computePathCosts();
    ++stats.rebuilds;
    last.fold = HeldUpdate::Fold::Refactorized;
  }

  /// L's rows from `first` on re-eliminated, the rows above kept (only H's columns from `first`
  /// on changed since L D L^T = H held: every change touched only variables placed there).
  /// Falls back to a whole refactorization when that one fails.
  void refreshFrom(int first) {
    if (first <= 0) {
      refresh();
      return;
    }
    if (!L.chol.refactorizeTrailing(H.upper(first), first)) {
      refresh();
      return;
    }
    sol.changedFrom(first);
    L.refresh_flops = L.flopsFrom(0);
    L.computePathCosts();
    ++stats.rebuilds;
    ++stats.partial_refactorizations;
    stats.partial_rows += H.capacity() - first;
    stats.partial_of_rows += H.capacity();
    last.fold = HeldUpdate::Fold::Partial;
  }

  /// The cost of re-eliminating L from row `first` (cost-model units), scanning no further
  /// once above `stop`.
  double partialCost(int first, double stop) {
    if (batch() || first <= 0) return std::numeric_limits<double>::infinity();
    return L.partialCap(first, H.Hx.size() - static_cast<std::size_t>(H.Hp[first]), stop);
  }

  /// The first row the queued change touches: new rows, deleted rows, the pieces' rows.
  int firstChangedRow(const std::vector<int>& new_identity_rows) const {
    int first = H.capacity();
    for (const std::vector<Piece>* ps : {&ups, &downs})
      for (const Piece& p : *ps)
        for (int j = 0; j < p.nvar; ++j) first = std::min(first, p.row[j]);
    for (int r : deleted_rows) first = std::min(first, r);
    for (int r : new_identity_rows) first = std::min(first, r);
    return first;
  }

  /// L's pattern cut to that of a factorization of H (CHOLMOD's resymbol): the entries that
  /// downdates and row deletions zeroed go, so every elimination-tree path is as short as a fresh
  /// factorization's (the queries walk them). No flops.
  void prune() {
    if (!L.stale_pattern) return;
    // The entries cut are zeros to the rounding of the downdates that cancelled them: the kept
    // solution stays that of L to rounding (HeldSolution).
    const bool ok = L.chol.pruneToPattern(H.upper());
    if (!ok) refresh();
    L.stale_pattern = false;
    L.computePathCosts();
  }

  bool degraded(double ratio) { return L.degraded(ratio, H.next_row, H.dead_rows); }

  /// A fresh ordering once the fill has grown past the bound (new variables go last, which
  /// fills more than AMD would).
  void checkFill() {
    if (degraded(params.reorder_fill_ratio)) reorder();
  }

  /// Brings L to H after a change already made to H (ups added, downs taken out, rows deleted,
  /// new variables' rows given): CHOLMOD's update (ups), row deletions, downdate (downs and the
  /// identity of the new rows), or a numeric refactorization when the cost model says that is
  /// cheaper (or a downdate lost definiteness to rounding); a fresh ordering when the fill has
  /// grown past the bound.
  void fold(const std::vector<int>& new_identity_rows) {
    if (batch()) {  // the batch path: no in-place change
      reorder();
      return;
    }
    const double cap = L.refreshCap(H.Hx.size());
    std::vector<char> deleted(static_cast<std::size_t>(H.capacity()), 0);
    for (int r : deleted_rows) deleted[r] = 1;
    static thread_local std::vector<int> up_p, up_i, down_p, down_i;
    static thread_local std::vector<double> up_x, down_x;
    double work = L.columns(ups, deleted, &up_p, &up_i, &up_x, cap);
    if (work <= cap) work += L.columns(downs, deleted, &down_p, &down_i, &down_x, cap - work);
    for (int r : deleted_rows)
      if (work <= cap) work += 2 * L.pathEntries(r, cap - work);
    // The third way: re-eliminate only the rows from the first one the change touched.
    const int first = firstChangedRow(new_identity_rows);
    last.first_changed_row = first;
    bool in_place = work <= cap;
    const double partial = partialCost(first, in_place ? work : cap);
    if (in_place && partial < work) in_place = false;
    bool ok = false;
    if (in_place) {
      for (int r : new_identity_rows) {
        down_i.push_back(r);
        down_x.push_back(1.0);
        down_p.push_back(static_cast<int>(down_i.size()));
      }
      ok = L.chol.updateInPlace(true, up_p, up_i, up_x);
      for (int r : deleted_rows) {
        if (!ok) break;
        ok = L.chol.deleteRowInPlace(r);
      }
      if (ok) ok = L.chol.updateInPlace(false, down_p, down_i, down_x);
      // Downdates and row deletions keep L's pattern (entries become zeros): taken out before
      // the next query that walks many paths (prune()).
      if (!downs.empty() || !deleted_rows.empty()) L.stale_pattern = true;
      if (ok) {
        sol.changedFrom(first);  // the rank updates' paths start at or after `first`
        ++stats.modifications;
        stats.folded_factors += ups.size() + downs.size();
        last.fold = HeldUpdate::Fold::InPlace;
      }
    }
    if (!ok) {
      if (partialCost(first, cap) < cap) {
        refreshFrom(first);
      } else {
        refresh();
      }
    }
    checkFill();
  }

  // ---- relinearization ----

  /// Relinearizes every factor on the variables `moved` (their `lin` already set) in H, then
  /// folds the change into L.
  void relinearize(const std::vector<int>& moved) {
    if (moved.empty()) return;
    last = HeldUpdate();
    last.relinearized_variables = moved.size();
    ups.clear();
    downs.clear();
    deleted_rows.clear();
    const std::vector<int>& ks = factorsOf(moved);
    last.relinearized_factors = ks.size();
    double work = 0;  // estimate: a downdate and an update of each row, from its first row
    for (int k : ks) {
      const Held& h = rec.factors[k];
      work += 2.0 * h.lin.rows * L.path_cost[rec.firstRow(h)];
    }
    const double cap = L.refreshCap(H.Hx.size());
    int first = H.capacity();
    for (int k : ks) first = std::min(first, rec.firstRow(rec.factors[k]));
    last.first_changed_row = first;
    bool in_place = !batch() && work <= cap;
    const double partial = partialCost(first, in_place ? work : cap);
    if (in_place && partial < work) in_place = false;
    const bool partly = !in_place && partial < cap;
    if (!in_place && !partly && ks.size() == rec.factor_count) {
      relinearizeAll(ks);
      return;
    }
    for (int k : ks) {
      Held& h = rec.factors[k];
      if (in_place) downs.push_back(rec.pieceOf(h));
      const LinearFactor old = h.lin;
      h.lin = rec.linearizeHeld(h);
      H.replace(rec, h, old);
      if (in_place) ups.push_back(rec.pieceOf(h));
    }
    if (in_place) {
      fold({});
    } else if (batch()) {
      reorder();
    } else if (partly) {
      refreshFrom(first);
      checkFill();
    } else {
      refresh();
      checkFill();
    }
  }

  /// The factors on the variables `vars`, each once (new_factors is the scratch).
  const std::vector<int>& factorsOf(const std::vector<int>& vars) {
    if (stamp.size() < rec.factors.size()) stamp.resize(rec.factors.size(), 0);
    if (++stamp_counter == 0) {
      std::fill(stamp.begin(), stamp.end(), 0u);
      stamp_counter = 1;
    }
    std::vector<int>& ks = new_factors;
    ks.clear();
    for (int v : vars)
      for (int k : rec.vars[v].factors) {
        if (stamp[k] == stamp_counter) continue;
        stamp[k] = stamp_counter;
        ks.push_back(k);
      }
    return ks;
  }

  /// Every factor relinearized (a full Gauss-Newton step): H assembled anew in one pass (no
  /// drift from taking out and adding in), refactorized in the kept order, or with a fresh
  /// ordering once the variables placed last since the last one have filled it past the
  /// queries' bound.
  void relinearizeAll(const std::vector<int>& ks) {
    for (int k : ks) rec.factors[k].lin = rec.linearizeHeld(rec.factors[k]);
    if (batch() || degraded(IncrementalFactorization::kQueryFillRatio)) {
      reorder();
    } else {
      H.assemble(rec);
      refresh();
      checkFill();
    }
  }

  // ---- folding the journal in: the named steps of sync() ----

  /// Step 1: variables the changes remove are marked dying, so the removals of their factors
  /// zero their rows of H instead of subtracting from them.
  void markDying(const GraphChange* first, const GraphChange* last_change) {
    H.dying_count = 0;
    for (const GraphChange* c = first; c != last_change; ++c)
      if (c->kind == GraphChange::Kind::RemoveVariable && c->index < rec.vars.size() &&
          rec.vars[c->index].alive && !rec.vars[c->index].dying) {
        rec.vars[c->index].dying = true;
        ++H.dying_count;
      }
  }

  /// Step 2: the journal into the records, in order; removed factors taken out of H (and
  /// queued as downdates of L), removed variables' rows queued for deletion.
  void applyJournal(const GraphChange* first, const GraphChange* last_change) {
    for (const GraphChange* c = first; c != last_change; ++c) {
      switch (c->kind) {
        case GraphChange::Kind::AddVariable:
          rec.addVar(c->index, c->variable);
          new_vars.push_back(static_cast<int>(c->index));
          break;
        case GraphChange::Kind::RemoveVariable: {
          const Var& r = rec.var(c->index);
          for (int t = 0; r.row >= 0 && t < r.dim; ++t) deleted_rows.push_back(r.row + t);
          rec.removeVar(c->index);
          ++last.removed_variables;
          break;
        }
        case GraphChange::Kind::AddFactor:
          new_factors.push_back(rec.addFactor(c->factor));
          break;
        case GraphChange::Kind::RemoveFactor: {
          const auto it = rec.factor_of.find(c->factor.id);
          if (it == rec.factor_of.end())
            throw std::logic_error("IncrementalFactorization: unknown factor removed");
          const Held& h = rec.factors[it->second];
          if (!h.added) {
            for (int j = 0; j < 2 && h.var[j] >= 0; ++j) rec.vars[h.var[j]].touched = change_count;
            downs.push_back(rec.pieceOf(h));
            H.add(rec, h, -1.0);
            ++last.removed_factors;
          }
          rec.removeFactor(it->second);
          break;
        }
      }
    }
    H.dying_count = 0;  // every dying variable is gone now
  }

  /// Step 3: the removed variables' rows leave H (identity rows until the next fresh ordering).
  void retireRows() {
    H.dead_rows += static_cast<int>(deleted_rows.size());
    for (int r : deleted_rows) {
      H.owner[r] = -1;
      H.Hx[H.Hp[r + 1] - 1] = 1.0;
      H.g[r] = 0;
      H.est[r] = 0;
    }
  }

  /// Step 4: new variables still there take their value as linearization point and the next
  /// spare rows (new variables last); their rows' identity is queued as a downdate. False when
  /// the spare rows ran out.
  bool placeNewVariables(const FactorGraph& graph) {
    bool room = true;
    for (int v : new_vars) {
      Var& r = rec.vars[v];
      if (!r.alive || r.row >= 0) continue;
      ++last.new_variables;
      r.lin = held::HeldRecords::valueIn(graph, r.key);
      if (H.next_row + r.dim > H.capacity()) {
        room = false;
        continue;
      }
      r.row = H.next_row;
      H.next_row += r.dim;
      for (int t = 0; t < r.dim; ++t) {
        H.owner[r.row + t] = v;
        identity_rows.push_back(r.row + t);
      }
      H.g.segment(r.row, r.dim).setZero();
      H.est.segment(r.row, r.dim) = r.lin.head(r.dim);
    }
    return room;
  }

  /// Step 5: the new factors still there linearized at their variables' points.
  std::vector<int> linearizeNewFactors() {
    std::vector<int> added;
    for (int k : new_factors) {
      Held& h = rec.factors[k];
      if (!h.alive || !h.added) continue;
      h.lin = rec.linearizeHeld(h);
      h.added = false;
      for (int j = 0; j < 2 && h.var[j] >= 0; ++j) rec.vars[h.var[j]].touched = change_count;
      added.push_back(k);
    }
    last.added_factors = added.size();
    return added;
  }

  /// Step 6: H's pattern extended by the new rows and factors (rebuilt when a new factor ties
  /// two variables H had no entry for), their A^T A added, their rows queued as updates of L.
  void extendH(int first_new_row, const std::vector<int>& added) {
    if (!H.extendPattern(rec, first_new_row, added)) {
      H.buildPattern(rec);  // values too
      last.pattern_rebuilt = true;
    } else {
      for (int k : added) H.add(rec, rec.factors[k], 1.0);
    }
    for (int k : added) ups.push_back(rec.pieceOf(rec.factors[k]));
  }

  /// Folds the graph's changes since the last sync into the records, H and L: the steps above,
  /// then fold() (step 7) brings L to H.
  void syncStructure(const FactorGraph& graph) {
    const GraphChange *first = nullptr, *last_change = nullptr;
    if (!built || graph.lineage() != lineage || !graph.changesSince(seq, &first, &last_change)) {
      readGraph(graph);
      reorder();
      return;
    }
    if (first == last_change) return;
    last = HeldUpdate();
    ups.clear();
    downs.clear();
    deleted_rows.clear();
    new_vars.clear();
    new_factors.clear();
    identity_rows.clear();
    markDying(first, last_change);
    const int first_new_row = H.next_row;
    applyJournal(first, last_change);
    seq = graph.changeCount();
    retireRows();
    const bool room = placeNewVariables(graph);
    const std::vector<int> added = linearizeNewFactors();
    if (!room) {
      reorder();
      return;
    }
    extendH(first_new_row, added);
    fold(identity_rows);
    ++change_count;
  }

  /// The graph's values against `est`, both in the graph's column order; a variable whose value
  /// was changed by anyone but this object takes it as estimate and linearization point.
  void syncValues(const FactorGraph& graph) {
    if (graph.valuesVersion() == values_version) return;
    const Eigen::VectorXd x = graph.values();
    const std::vector<VariableIndex>& index = graph.variableIndices();
    const std::vector<int>& starts = graph.variableStarts();
    std::vector<int> moved;
    for (std::size_t k = 0; k < index.size(); ++k) {
      Var& r = rec.vars[index[k]];
      const auto value = x.segment(starts[k], r.dim);
      if (value != H.est.segment(r.row, r.dim)) {
        H.est.segment(r.row, r.dim) = value;
        r.lin.head(r.dim) = value;
        moved.push_back(static_cast<int>(index[k]));
      }
    }
    values_version = graph.valuesVersion();
    relinearize(moved);
  }

  void sync(const FactorGraph& graph) {
    syncStructure(graph);
    syncValues(graph);
  }

  // ---- Gauss-Newton ----

  /// Variables whose estimate left their linearization point by more than `threshold` take the
  /// estimate as their new linearization point; their factors are relinearized.
  void relinearizeMoved(double threshold) {
    std::vector<int> moved;
    for (int v = 0; v < static_cast<int>(rec.vars.size()); ++v) {
      Var& r = rec.vars[v];
      if (!r.alive) continue;
      if (maxAbsDifference(r.dim, H.est.data() + r.row, r.lin.data()) > threshold) {
        r.lin.head(r.dim) = H.est.segment(r.row, r.dim);
        moved.push_back(v);
      }
    }
    stats.moved_variables += moved.size();
    relinearize(moved);
  }

  /// est = lin + dx with dx = -H^-1 g (the minimizer of the linearized cost), dx solved again
  /// only in the rows that changed (HeldSolution; `wildfire` [m, rad]: a row's change below it
  /// does not spread to the rows that depend on it); only the variables of those rows are
  /// written. Returns the largest change of est.
  double solveEstimate(double wildfire) {
    sol.solve(*L.chol.factor(), H.g, wildfire);
    ++stats.solves;
    stats.solved_rows += static_cast<double>(sol.rows.size());
    stats.solve_of_rows += static_cast<double>(H.capacity());
    if (var_stamp.size() < rec.vars.size()) var_stamp.resize(rec.vars.size(), 0);
    if (++var_stamp_counter == 0) {
      std::fill(var_stamp.begin(), var_stamp.end(), 0u);
      var_stamp_counter = 1;
    }
    double change = 0;
    for (int row : sol.rows) {
      const int v = H.owner[row];
      if (v < 0 || var_stamp[v] == var_stamp_counter) continue;
      var_stamp[v] = var_stamp_counter;
      const Var& r = rec.vars[v];
      Eigen::Vector3d x = r.lin;
      x.head(r.dim) += sol.dx.segment(r.row, r.dim);
      if (r.key.kind == VariableKey::Kind::Pose) x.z() = wrapAngle(x.z());
      change = std::max(change, maxAbsDifference(r.dim, x.data(), H.est.data() + r.row));
      H.est.segment(r.row, r.dim) = x.head(r.dim);
    }
    return change;
  }

  /// `est` into the graph (in its column order).
  void writeEstimate(FactorGraph& graph) {
    Eigen::VectorXd x(graph.dim());
    int c = 0;
    for (VariableIndex v : graph.variableIndices()) {
      const Var& r = rec.vars[v];
      x.segment(c, r.dim) = H.est.segment(r.row, r.dim);
      c += r.dim;
    }
    graph.setValues(x);
    values_version = graph.valuesVersion();
  }

  /// A vector by row of H (`by_row(var)`: its values) in `graph`'s column layout.
  template <typename Fn>
  Eigen::VectorXd inGraphLayout(const FactorGraph& graph, Fn by_row) const {
    Eigen::VectorXd out(graph.dim());
    int c = 0;
    for (VariableIndex v : graph.variableIndices()) {
      const Var& r = rec.vars[v];
      out.segment(c, r.dim) = by_row(r);
      c += r.dim;
    }
    return out;
  }
};

IncrementalFactorization::IncrementalFactorization(const HeldFactorParams& params)
    : s_(std::make_unique<State>(params)) {}

IncrementalFactorization::~IncrementalFactorization() = default;

IncrementalFactorization::IncrementalFactorization(const IncrementalFactorization& o)
    : s_(std::make_unique<State>(*o.s_)) {}

void IncrementalFactorization::adopt(const FactorGraph& copy) { s_->lineage = copy.lineage(); }

bool IncrementalFactorization::isCurrent(const FactorGraph& graph) const {
  const State& s = *s_;
  return s.built && s.lineage == graph.lineage() && s.seq == graph.changeCount() &&
         s.values_version == graph.valuesVersion();
}

void IncrementalFactorization::sync(const FactorGraph& graph) { s_->sync(graph); }

const SparseCholesky& IncrementalFactorization::factor(const FactorGraph& graph, bool at_estimate) {
  State& s = *s_;
  s.sync(graph);
  if (at_estimate) {
    // Every variable the last step moved takes the estimate as its linearization point.
    s.relinearizeMoved(0.0);
    s.prune();
    if (s.degraded(kQueryFillRatio) || s.L.meanDepth(s.H.owner) > kQueryFillRatio * s.L.fresh_depth)
      s.reorder();
  }
  if (!s.L.map_valid || s.L.map_variables != graph.variablesVersion()) {
    // The graph's columns (poses by step, then landmarks by id) to the rows of H.
    std::vector<int> map;
    map.reserve(static_cast<std::size_t>(graph.dim()));
    for (VariableIndex v : graph.variableIndices()) {
      const Var& r = s.rec.vars[v];
      for (int t = 0; t < r.dim; ++t) map.push_back(r.row + t);
    }
    s.L.chol.setColumnMap(std::move(map));
    s.L.map_valid = true;
    s.L.map_variables = graph.variablesVersion();
  }
  return s.L.chol;
}

SolveReport IncrementalFactorization::iterate(FactorGraph& graph, const IncrementalStep& step) {
  State& s = *s_;
  s.sync(graph);
  SolveReport rep;
  const bool exact = step.relinearize_threshold <= 0;
  for (int it = 0; it < step.max_iterations; ++it) {
    if (step.stop_on_request) Cancellation::check();
    s.relinearizeMoved(step.relinearize_threshold);
    if (it == 0) rep.initial_chi2 = s.H.chi2;
    // With every variable at its linearization point chi2 is the cost of the estimate: a step
    // that raised it beyond rounding (diverging, far from the optimum) is undone, and it stops.
    if (exact && it > 0 && s.H.chi2 > rep.final_chi2 * (1 + 1e-9)) {
      s.H.est = s.est_before;
      s.sol.invalidate();  // the kept solution is no longer est - lin
      s.relinearizeMoved(0);
      s.writeEstimate(graph);
      break;
    }
    rep.final_chi2 = s.H.chi2;
    if (exact) s.est_before = s.H.est;
    const double change = s.solveEstimate(step.wildfire_threshold);
    s.writeEstimate(graph);
    rep.iterations = it + 1;
    rep.last_step_norm = change;
    if (change < step.step_tolerance) {
      rep.converged = true;
      break;
    }
    if (exact && step.relative_chi2_tolerance > 0 && it > 0 &&
        rep.initial_chi2 - s.H.chi2 <= step.relative_chi2_tolerance * rep.initial_chi2) {
      rep.converged = true;
      break;
    }
  }
  return rep;
}

Eigen::VectorXd IncrementalFactorization::step(const FactorGraph& graph) {
  State& s = *s_;
  s.sync(graph);
  const Eigen::VectorXd dx = -s.L.chol.solve(s.H.g);
  return s.inGraphLayout(graph, [&](const Var& r) { return dx.segment(r.row, r.dim); });
}

Eigen::VectorXd IncrementalFactorization::linearizationPoint(const FactorGraph& graph) {
  State& s = *s_;
  s.sync(graph);
  return s.inGraphLayout(graph, [](const Var& r) { return r.lin.head(r.dim); });
}

double IncrementalFactorization::chi2() const { return s_->H.chi2; }

const IncrementalStats& IncrementalFactorization::stats() const { return s_->stats; }

const HeldUpdate& IncrementalFactorization::lastUpdate() const { return s_->last; }

}  // namespace budget_slam::graph
