#include "budget_slam/graph/IncrementalFactorization.h"

#include <cholmod.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "budget_slam/core/Cancellation.h"

namespace budget_slam::graph {

namespace {
/// Spare rows for new variables after a fresh ordering: a quarter of the used ones, at least
/// this many (64 poses).
constexpr int kMinSpareRows = 192;

/// Cost model of a change (docs/GRAPH.md "Held factor"): CHOLMOD's rank-1 update or downdate
/// touches every entry of L on the elimination-tree path from its first row to the root; a
/// numeric refactorization does the flops of the factorization and reads H. Per unit, measured
/// on the machine of docs/PERFORMANCE.md; only the ratio matters, the cheaper way is taken.
constexpr double kUpdateCostPerEntry = 2.5;  ///< [ns] per entry of L on a rank-1 path
constexpr double kRefreshCostPerFlop = 0.7;  ///< [ns] per flop of the simplicial factorization
constexpr double kRefreshCostPerEntry = 20;  ///< [ns] per entry of H

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

struct IncrementalFactorization::State {
  /// A variable of the held factor: its rows of H and its linearization point.
  struct Var {
    VariableKey key;
    int row = -1;  ///< first row of H, its position in the elimination order; -1 until placed
    int dim = 0;
    Eigen::Vector3d lin = Eigen::Vector3d::Zero();
    std::vector<int> factors;  ///< indices into `factors`
    bool alive = false;
    bool dying = false;  ///< removed by the changes being folded in
  };
  /// A factor folded into H, with the rows it put there and where its entries of H are.
  struct Held {
    GraphFactor f;
    std::array<int, 2> var{{-1, -1}};
    LinearFactor lin;
    std::vector<int> hpos;           ///< index into Hx of each of its entries
    std::vector<std::uint8_t> hidx;  ///< ... and of the value in A^T A (column-major 6 x 6)
    bool alive = false;
    bool added = false;  ///< added since the last change was folded in (not in H yet)
  };
  /// Rows to add to or take from H: a factor's linearization on its variables' rows.
  struct Piece {
    LinearFactor lin;
    int nvar = 0;
    std::array<int, 2> row{{-1, -1}};
    std::array<int, 2> dim{{0, 0}};
  };

  explicit State(double ratio) : reorder_fill_ratio(ratio) {}

  double reorder_fill_ratio;
  std::vector<Var> vars;  ///< by VariableIndex (FactorGraph::variableIndices)
  std::vector<Held> factors;
  std::vector<int> free_factors;
  std::unordered_map<FactorId, int> factor_of;
  std::size_t factor_count = 0;
  /// Variable of each row of H, -1 for a spare or dead row (an identity row of H).
  std::vector<int> owner;
  int next_row = 0;     ///< first spare row
  int dying_count = 0;  ///< variables marked dying (syncStructure)
  int dead_rows = 0;    ///< rows of removed variables since the last fresh ordering
  /// H's upper triangle in compressed columns, rows in elimination order (the factor is
  /// P H P^T with P = I): kept equal to the sum of the factors' A^T A.
  std::vector<int> Hp, Hi;
  std::vector<double> Hx;
  Eigen::VectorXd g;    ///< sum of A^T r, by row
  Eigen::VectorXd est;  ///< the estimate the graph holds, by row (a pose's yaw wrapped)
  double chi2 = 0;      ///< sum of |r|^2 at the linearization points
  SparseCholesky chol;
  bool built = false;
  std::uint64_t lineage = 0, seq = 0, values_version = 0;
  bool map_valid = false;
  std::uint64_t map_variables = 0;  ///< FactorGraph::variablesVersion() of the column map
  double fresh_fill = 0;            ///< nnz(L) per used row right after the last fresh ordering
  double fresh_flops = 0;      ///< factorization flops per used row after the last fresh ordering
  double fresh_depth = 0;      ///< meanDepth() after the last fresh ordering
  double refresh_flops = 0;    ///< flops of the last numeric factorization
  bool stale_pattern = false;  ///< L holds entries a factorization of H would not have
  IncrementalStats stats;
  // Scratch of one change.
  std::vector<Piece> ups, downs;
  std::vector<int> deleted_rows, new_vars, new_factors;
  std::vector<unsigned> stamp;
  unsigned stamp_counter = 0;
  Eigen::VectorXd est_before;  ///< iterate(): the estimate before the last step

  int capacity() const { return static_cast<int>(owner.size()); }

  // -- records --
  Var& var(VariableIndex v) {
    if (v >= vars.size() || !vars[v].alive)
      throw std::logic_error("IncrementalFactorization: unknown variable");
    return vars[v];
  }
  void addVar(VariableIndex v, const VariableKey& key) {
    if (v >= vars.size()) vars.resize(static_cast<std::size_t>(v) + 1);
    Var& r = vars[v];
    if (r.alive) throw std::logic_error("IncrementalFactorization: variable added twice");
    r = Var();
    r.key = key;
    r.dim = static_cast<int>(key.dim());
    r.alive = true;
  }
  void removeVar(VariableIndex v) {
    Var& r = var(v);
    if (!r.factors.empty())
      throw std::logic_error("IncrementalFactorization: variable removed with factors");
    r.alive = false;
    r.dying = false;
  }
  int addFactor(const GraphFactor& f) {
    int k;
    if (!free_factors.empty()) {
      k = free_factors.back();
      free_factors.pop_back();
    } else {
      k = static_cast<int>(factors.size());
      factors.emplace_back();
    }
    Held& h = factors[k];
    h.f = f;
    h.alive = true;
    h.added = true;
    h.hpos.clear();
    h.var = {{-1, -1}};
    for (int j = 0; j < f.variableCount(); ++j) {
      var(f.vars[j]).factors.push_back(k);
      h.var[j] = static_cast<int>(f.vars[j]);
    }
    factor_of[f.id] = k;
    ++factor_count;
    return k;
  }
  void removeFactor(int k) {
    Held& h = factors[k];
    for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
      std::vector<int>& fs = vars[h.var[j]].factors;
      fs.erase(std::find(fs.begin(), fs.end(), k));
    }
    factor_of.erase(h.f.id);
    h.alive = false;
    free_factors.push_back(k);
    --factor_count;
  }
  LinearFactor linearizeHeld(const Held& h) const {
    return linearize(h.f, vars[h.var[0]].lin,
                     h.var[1] >= 0 ? vars[h.var[1]].lin : Eigen::Vector3d::Zero());
  }
  Piece pieceOf(const Held& h) const {
    Piece p;
    p.lin = h.lin;
    for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
      p.row[j] = vars[h.var[j]].row;
      p.dim[j] = vars[h.var[j]].dim;
      p.nvar = j + 1;
    }
    return p;
  }
  static Eigen::Vector3d valueIn(const FactorGraph& graph, const VariableKey& key) {
    if (key.kind == VariableKey::Kind::Pose) return graph.pose(static_cast<StepIndex>(key.id)).x;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    v.head<2>() = graph.landmark(key.id).x;
    return v;
  }

  /// Every entry (r <= c) a factor puts into H's upper triangle, in a fixed order: fn(r, c,
  /// column of A for r, column of A for c).
  template <typename Fn>
  void forEachEntry(const Held& h, Fn fn) const {
    const int nv = h.var[1] >= 0 ? 2 : 1;
    int off[2] = {0, 0};
    if (nv == 2) off[1] = vars[h.var[0]].dim;
    for (int x = 0; x < nv; ++x)
      for (int y = 0; y < nv; ++y) {
        const Var &a = vars[h.var[x]], &b = vars[h.var[y]];
        for (int i = 0; i < a.dim; ++i)
          for (int j = 0; j < b.dim; ++j)
            if (a.row + i <= b.row + j) fn(a.row + i, b.row + j, off[x] + i, off[y] + j);
      }
  }

  /// Adds sign * A^T A of a factor to H (at its hpos), sign * A^T r to g, sign * |r|^2 to chi2.
  /// Entries on a dying row are set to zero instead (the row leaves H).
  void addToH(const Held& h, double sign) { changeInH(h, h.lin, sign, nullptr); }
  /// H, g and chi2 from `old` to the factor's own linearization: one pass over its entries.
  void replaceInH(const Held& h, const LinearFactor& old) { changeInH(h, h.lin, 1.0, &old); }
  void changeInH(const Held& h, const LinearFactor& lf, double sign, const LinearFactor* old) {
    // A and r are zero past their rows and columns: fixed-size products.
    Eigen::Matrix<double, 6, 6> AtA = sign * (lf.A.transpose() * lf.A);
    Eigen::Matrix<double, 6, 1> Atr = sign * (lf.A.transpose() * lf.r);
    double r2 = sign * lf.r.squaredNorm();
    if (old) {
      AtA.noalias() -= old->A.transpose() * old->A;
      Atr.noalias() -= old->A.transpose() * old->r;
      r2 -= old->r.squaredNorm();
    }
    const double* a = AtA.data();
    const std::size_t m = h.hpos.size();
    if (dying_count == 0) {
      for (std::size_t k = 0; k < m; ++k) Hx[h.hpos[k]] += a[h.hidx[k]];
    } else {
      std::size_t k = 0;
      forEachEntry(h, [&](int r, int c, int, int) {
        double& x = Hx[h.hpos[k]];
        x = dyingRow(r) || dyingRow(c) ? 0.0 : x + a[h.hidx[k]];
        ++k;
      });
    }
    int off = 0;
    for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
      const Var& v = vars[h.var[j]];
      if (!v.dying) g.segment(v.row, v.dim) += Atr.segment(off, v.dim);
      off += v.dim;
    }
    chi2 += r2;
  }
  bool dyingRow(int r) const { return owner[r] >= 0 && vars[owner[r]].dying; }

  /// Index into Hx of entry (r, c), r <= c, or -1 when H has none there.
  int find(int r, int c) const {
    const auto b = Hi.begin() + Hp[c], e = Hi.begin() + Hp[c + 1];
    const auto it = std::lower_bound(b, e, r);
    return it != e && *it == r ? static_cast<int>(it - Hi.begin()) : -1;
  }

  /// H's pattern and values from every factor (after a fresh ordering, or when a factor ties
  /// two variables that had no entry yet): every diagonal entry, the factors' entries.
  void buildPattern() {
    const int n = capacity();
    std::vector<int> count(static_cast<std::size_t>(n) + 1, 1);  // the diagonals
    for (const Held& h : factors)
      if (h.alive)
        forEachEntry(h, [&](int r, int c, int, int) {
          if (r != c) ++count[c];
        });
    std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
    for (int c = 0; c < n; ++c) start[c + 1] = start[c] + count[c];
    std::vector<int> rows(static_cast<std::size_t>(start[n]));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int c = 0; c < n; ++c) rows[fill[c]++] = c;
    for (const Held& h : factors)
      if (h.alive)
        forEachEntry(h, [&](int r, int c, int, int) {
          if (r != c) rows[fill[c]++] = r;
        });
    Hp.assign(static_cast<std::size_t>(n) + 1, 0);
    Hi.clear();
    Hi.reserve(rows.size());
    for (int c = 0; c < n; ++c) {
      std::sort(rows.begin() + start[c], rows.begin() + start[c + 1]);
      const auto e = std::unique(rows.begin() + start[c], rows.begin() + start[c + 1]);
      Hi.insert(Hi.end(), rows.begin() + start[c], e);
      Hp[c + 1] = static_cast<int>(Hi.size());
    }
    for (Held& h : factors)
      if (h.alive) locate(&h);
    assemble();
  }

  /// H, g and chi2 from every factor's linearization on the pattern as it stands.
  void assemble() {
    const int n = capacity();
    Hx.assign(Hi.size(), 0.0);
    g.setZero(n);
    chi2 = 0;
    for (const Held& h : factors)
      if (h.alive) addToH(h, 1.0);
    for (int r = 0; r < n; ++r)
      if (owner[r] < 0) Hx[Hp[r + 1] - 1] = 1.0;  // spare or dead: identity
  }

  /// hpos of a factor from H's pattern; false when an entry is missing.
  bool locate(Held* h) {
    h->hpos.clear();
    h->hidx.clear();
    bool ok = true;
    forEachEntry(*h, [&](int r, int c, int ar, int ac) {
      const int k = find(r, c);
      ok = ok && k >= 0;
      h->hpos.push_back(k);
      h->hidx.push_back(static_cast<std::uint8_t>(6 * ac + ar));
    });
    return ok;
  }

  /// New columns from `first` on (rows of variables placed since the last change, and spares):
  /// the entries of the new factors there, and every diagonal. False when a new factor has an
  /// entry in an older column that H has no place for (buildPattern() then).
  bool extendPattern(int first, const std::vector<int>& added) {
    const int n = capacity();
    std::vector<std::pair<int, int>> entries;  // (column, row)
    for (int c = first; c < n; ++c) entries.emplace_back(c, c);
    for (int k : added)
      forEachEntry(factors[k], [&](int r, int c, int, int) {
        if (c >= first && r != c) entries.emplace_back(c, r);
      });
    std::sort(entries.begin(), entries.end());
    entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
    Hi.resize(static_cast<std::size_t>(Hp[first]));
    Hx.resize(static_cast<std::size_t>(Hp[first]));
    Hp.resize(static_cast<std::size_t>(n) + 1);
    std::size_t e = 0;
    for (int c = first; c < n; ++c) {
      for (; e < entries.size() && entries[e].first == c; ++e) {
        Hi.push_back(entries[e].second);
        Hx.push_back(0.0);
      }
      Hp[c + 1] = static_cast<int>(Hi.size());
      if (owner[c] < 0) Hx.back() = 1.0;  // spare: identity
    }
    for (int k : added)
      if (!locate(&factors[k])) return false;
    return true;
  }

  /// Every variable and factor of `graph` afresh (the first time, or when the journal no longer
  /// reaches back to the last change folded in).
  void readGraph(const FactorGraph& graph) {
    vars.clear();
    factors.clear();
    free_factors.clear();
    factor_of.clear();
    factor_count = 0;
    for (const auto& [s, p] : graph.poses()) {
      addVar(p.index, VariableKey::pose(s));
      vars[p.index].lin = p.x;
    }
    for (const auto& [id, l] : graph.landmarks()) {
      addVar(l.index, VariableKey::landmark(id));
      vars[l.index].lin.head<2>() = l.x;
    }
    for (const GraphFactor& f : graph.factors()) addFactor(f);
    for (Held& h : factors) {
      h.lin = linearizeHeld(h);
      h.added = false;
    }
    lineage = graph.lineage();
    seq = graph.changeCount();
    values_version = graph.valuesVersion();
    built = false;
    est.resize(0);  // the estimate is the graph's values: reorder() takes them from `lin`
  }

  // -- the factor --
  /// L's columns and elimination tree as CHOLMOD holds them (simplicial, rows ascending).
  struct Tree {
    const int *p, *nz, *i;
    int n;
    int parent(int k) const { return nz[k] > 1 ? i[p[k] + 1] : -1; }
  };
  Tree tree() {
    const cholmod_factor& L = *chol.factor();
    return {static_cast<const int*>(L.p), static_cast<const int*>(L.nz),
            static_cast<const int*>(L.i), static_cast<int>(L.n)};
  }
  double nonZerosOfL() {
    const Tree t = tree();
    double s = 0;
    for (int k = 0; k < t.n; ++k) s += t.nz[k];
    return s;
  }
  /// H as CHOLMOD reads it. Rows of removed variables keep their entries in Hp/Hi (zeros: the
  /// factors' positions stay valid) until the next fresh ordering; a factorization or a pattern
  /// cut reads a copy without them, so they leave no fill behind.
  SparseCholesky::UpperTriangle upper() {
    SparseCholesky::UpperTriangle H;
    H.n = capacity();
    if (dead_rows == 0) {
      H.p = Hp.data();
      H.i = Hi.data();
      H.x = Hx.data();
      return H;
    }
    Fp.assign(static_cast<std::size_t>(H.n) + 1, 0);
    Fi.clear();
    Fx.clear();
    for (int c = 0; c < H.n; ++c) {
      for (int k = Hp[c]; k < Hp[c + 1]; ++k) {
        const int r = Hi[k];
        if (r != c && (owner[r] < 0 || owner[c] < 0)) continue;
        Fi.push_back(r);
        Fx.push_back(Hx[k]);
      }
      Fp[c + 1] = static_cast<int>(Fi.size());
    }
    H.p = Fp.data();
    H.i = Fi.data();
    H.x = Fx.data();
    return H;
  }
  std::vector<int> Fp, Fi;
  std::vector<double> Fx;

  /// A fresh fill-reducing ordering: AMD on the variable graph, postordered; the variables'
  /// rows renumbered in that order, spare rows after; H rebuilt and factorized (the factors keep
  /// their linearizations).
  void reorder() {
    std::vector<int> alive;
    for (int v = 0; v < static_cast<int>(vars.size()); ++v)
      if (vars[v].alive) alive.push_back(v);
    const int nv = static_cast<int>(alive.size());
    std::vector<int> node(vars.size(), -1);
    for (int k = 0; k < nv; ++k) node[alive[k]] = k;
    // Strict upper triangle of the variable graph.
    std::vector<std::vector<int>> adj(static_cast<std::size_t>(nv));
    for (const Held& h : factors)
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
    const std::vector<int> order = chol.orderNodes(nv, p, i);
    // The estimate moves with its variables (it is the linearization point plus the last step).
    std::vector<Eigen::Vector3d> estimate(static_cast<std::size_t>(nv));
    for (int k = 0; k < nv; ++k) {
      const Var& r = vars[alive[k]];
      estimate[k] = r.lin;
      if (r.row >= 0 && r.row + r.dim <= est.size())
        estimate[k].head(r.dim) = est.segment(r.row, r.dim);
    }
    int row = 0;
    for (int k : order) {
      Var& r = vars[alive[k]];
      r.row = row;
      row += r.dim;
    }
    next_row = row;
    owner.assign(static_cast<std::size_t>(row + std::max(kMinSpareRows, row / 4)), -1);
    est.setZero(capacity());
    for (int k = 0; k < nv; ++k) {
      Var& r = vars[alive[k]];
      for (int t = 0; t < r.dim; ++t) owner[r.row + t] = alive[k];
      est.segment(r.row, r.dim) = estimate[k].head(r.dim);
    }
    dead_rows = 0;
    buildPattern();
    chol.setColumnMap({});
    map_valid = false;
    built = false;
    if (!chol.factorizeInOrder(upper()))
      throw std::runtime_error("graph: information matrix is not positive definite");
    built = true;
    stale_pattern = false;
    refresh_flops = chol.analysedFlops();
    fresh_fill = nonZerosOfL() / std::max(1, next_row);
    fresh_flops = refresh_flops / std::max(1, next_row);
    fresh_depth = meanDepth();
    computePathCosts();
    ++stats.rebuilds;
    ++stats.fresh_orderings;
  }

  /// L from H by a numeric refactorization in the kept order and storage.
  void refresh() {
    if (!chol.refactorizeInOrder(upper())) {
      built = false;
      throw std::runtime_error("graph: information matrix is not positive definite");
    }
    refresh_flops = chol.lastFactorizationFlops();
    stale_pattern = false;
    computePathCosts();
    ++stats.rebuilds;
  }

  /// L's pattern cut to that of a factorization of H (CHOLMOD's resymbol): the entries that
  /// downdates and row deletions zeroed go, so every elimination-tree path is as short as a fresh
  /// factorization's (the queries walk them). No flops.
  void prune() {
    if (!stale_pattern) return;
    const bool ok = chol.pruneToPattern(upper());
    if (!ok) refresh();
    stale_pattern = false;
    computePathCosts();
  }

  /// Entries of L on the etree path from every position to the root, as L stood at the last
  /// factorization (cost model estimates before the exact walk of pathEntries).
  std::vector<double> path_cost;
  void computePathCosts() {
    const Tree t = tree();
    path_cost.assign(static_cast<std::size_t>(t.n), 0.0);
    for (int k = t.n - 1; k >= 0; --k) {  // a parent comes after its children
      const int up = t.parent(k);
      path_cost[k] = t.nz[k] + (up >= 0 ? path_cost[up] : 0.0);
    }
  }
  /// Mean depth of the rows of live variables in L's elimination tree: the length of the paths
  /// every partial inverse walks (the variables placed last since the last fresh ordering lie
  /// on all of them).
  double meanDepth() {
    const Tree t = tree();
    std::vector<int> depth(static_cast<std::size_t>(t.n), 1);
    double sum = 0, count = 0;
    for (int k = t.n - 1; k >= 0; --k) {
      const int up = t.parent(k);
      if (up >= 0) depth[k] = 1 + depth[up];
      if (owner[k] >= 0) sum += depth[k], ++count;
    }
    return count > 0 ? sum / count : 0.0;
  }
  /// The cost-model bound on in-place work: that of a numeric refactorization, in entries.
  double refreshCap() const {
    return (kRefreshCostPerFlop * refresh_flops +
            kRefreshCostPerEntry * static_cast<double>(Hx.size())) /
           kUpdateCostPerEntry;
  }

  /// Entries of L on the etree path from position k to the root (the work of a rank-1 change
  /// that starts there), stopping once above `cap`.
  double pathEntries(int k, double cap) {
    const Tree t = tree();
    double s = 0;
    for (; k >= 0 && s <= cap; k = t.parent(k)) s += t.nz[k];
    return s;
  }

  /// The pieces' rows as columns of C (H +-= C C^T), rows ascending; rows in `deleted` left
  /// out. Returns the work of the columns by the cost model (stopping once above `cap`).
  double columns(const std::vector<Piece>& pieces, const std::vector<char>& deleted,
                 std::vector<int>* cp, std::vector<int>* ci, std::vector<double>* cx, double cap) {
    cp->assign(1, 0);
    ci->clear();
    cx->clear();
    double work = 0;
    for (const Piece& p : pieces) {
      // Variables by row, so each column's rows come out ascending.
      const bool swap = p.nvar == 2 && p.row[1] < p.row[0];
      const int first = swap ? 1 : 0;
      const int off[2] = {0, p.dim[0]};
      for (int i = 0; i < p.lin.rows; ++i) {
        const std::size_t begin = ci->size();
        for (int q = 0; q < p.nvar; ++q) {
          const int a = q == 0 ? first : 1 - first;
          for (int t = 0; t < p.dim[a]; ++t) {
            const int row = p.row[a] + t;
            const double x = p.lin.A(i, off[a] + t);
            if (x != 0 && !deleted[row]) {
              ci->push_back(row);
              cx->push_back(x);
            }
          }
        }
        if (ci->size() == begin) continue;
        if (work <= cap) work += pathEntries((*ci)[begin], cap - work);
        cp->push_back(static_cast<int>(ci->size()));
      }
    }
    return work;
  }

  /// Brings L to H after a change already made to H (ups added, downs taken out, rows deleted,
  /// new variables' rows given): CHOLMOD's update (ups), row deletions, downdate (downs and the
  /// identity of the new rows), or a numeric refactorization when the cost model says that is
  /// cheaper (or a downdate lost definiteness to rounding); a fresh ordering when the fill has
  /// grown past the bound.
  void fold(const std::vector<int>& identity_rows) {
    if (reorder_fill_ratio <= 1) {  // the batch path: no in-place change
      reorder();
      return;
    }
    const double cap = refreshCap();
    std::vector<char> deleted(static_cast<std::size_t>(capacity()), 0);
    for (int r : deleted_rows) deleted[r] = 1;
    static thread_local std::vector<int> up_p, up_i, down_p, down_i;
    static thread_local std::vector<double> up_x, down_x;
    double work = columns(ups, deleted, &up_p, &up_i, &up_x, cap);
    if (work <= cap) work += columns(downs, deleted, &down_p, &down_i, &down_x, cap - work);
    for (int r : deleted_rows)
      if (work <= cap) work += 2 * pathEntries(r, cap - work);
    bool ok = false;
    if (work <= cap) {
      for (int r : identity_rows) {
        down_i.push_back(r);
        down_x.push_back(1.0);
        down_p.push_back(static_cast<int>(down_i.size()));
      }
      ok = chol.updateInPlace(true, up_p, up_i, up_x);
      for (int r : deleted_rows) {
        if (!ok) break;
        ok = chol.deleteRowInPlace(r);
      }
      if (ok) ok = chol.updateInPlace(false, down_p, down_i, down_x);
      // Downdates and row deletions keep L's pattern (entries become zeros): taken out before
      // the next query that walks many paths (prune()).
      if (!downs.empty() || !deleted_rows.empty()) stale_pattern = true;
      if (ok) {
        ++stats.modifications;
        stats.folded_factors += ups.size() + downs.size();
      }
    }
    if (!ok) refresh();
    checkFill();
  }

  /// A fresh ordering once the fill has grown past the bound (new variables go last, which
  /// fills more than AMD would).
  void checkFill() {
    if (degraded(reorder_fill_ratio)) reorder();
  }
  /// The fill per row (nnz(L), or the flops of the last factorization) past `ratio` times the one
  /// right after the last fresh ordering.
  /// Also when a tenth of the rows belong to removed variables (their places in the kept order
  /// no longer fit the graph: mass pose marginalization, a bounded graph's window).
  bool degraded(double ratio) {
    const double rows = next_row - dead_rows;
    if (rows <= 0) return false;
    return (nonZerosOfL() - dead_rows) / rows > ratio * fresh_fill ||
           refresh_flops / rows > ratio * fresh_flops || dead_rows > 0.1 * next_row;
  }

  /// Relinearizes every factor on the variables `moved` (their `lin` already set) in H, then
  /// folds the change into L.
  void relinearize(const std::vector<int>& moved) {
    if (moved.empty()) return;
    ups.clear();
    downs.clear();
    deleted_rows.clear();
    if (stamp.size() < factors.size()) stamp.resize(factors.size(), 0);
    if (++stamp_counter == 0) {
      std::fill(stamp.begin(), stamp.end(), 0u);
      stamp_counter = 1;
    }
    std::vector<int>& ks = new_factors;  // scratch: the factors to relinearize
    ks.clear();
    double work = 0;  // estimate: a downdate and an update of each row, from its first row
    for (int v : moved)
      for (int k : vars[v].factors) {
        if (stamp[k] == stamp_counter) continue;
        stamp[k] = stamp_counter;
        ks.push_back(k);
        const Held& h = factors[k];
        int first = vars[h.var[0]].row;
        if (h.var[1] >= 0) first = std::min(first, vars[h.var[1]].row);
        work += 2.0 * h.lin.rows * path_cost[first];
      }
    const bool in_place = reorder_fill_ratio > 1 && work <= refreshCap();
    if (!in_place && ks.size() == factor_count) {
      // Every factor (a full Gauss-Newton step): H assembled anew in one pass (no drift from
      // taking out and adding in), refactorized in the kept order, or with a fresh ordering once
      // the variables placed last since the last one have filled it past the queries' bound.
      for (int k : ks) factors[k].lin = linearizeHeld(factors[k]);
      if (reorder_fill_ratio <= 1 || degraded(IncrementalFactorization::kQueryFillRatio)) {
        reorder();
      } else {
        assemble();
        refresh();
        checkFill();
      }
      return;
    }
    for (int k : ks) {
      Held& h = factors[k];
      if (in_place) downs.push_back(pieceOf(h));
      const LinearFactor old = h.lin;
      h.lin = linearizeHeld(h);
      replaceInH(h, old);
      if (in_place) ups.push_back(pieceOf(h));
    }
    if (in_place) {
      fold({});
    } else if (reorder_fill_ratio <= 1) {
      reorder();
    } else {
      refresh();
      checkFill();
    }
  }

  /// Folds the graph's changes since the last sync into the records, H and L.
  void syncStructure(const FactorGraph& graph) {
    const GraphChange *first = nullptr, *last = nullptr;
    if (!built || graph.lineage() != lineage || !graph.changesSince(seq, &first, &last)) {
      readGraph(graph);
      reorder();
      return;
    }
    if (first == last) return;
    dying_count = 0;
    for (const GraphChange* c = first; c != last; ++c)
      if (c->kind == GraphChange::Kind::RemoveVariable && c->index < vars.size() &&
          vars[c->index].alive && !vars[c->index].dying) {
        vars[c->index].dying = true;
        ++dying_count;
      }
    ups.clear();
    downs.clear();
    deleted_rows.clear();
    new_vars.clear();
    new_factors.clear();
    const int first_new_row = next_row;
    for (const GraphChange* c = first; c != last; ++c) {
      switch (c->kind) {
        case GraphChange::Kind::AddVariable:
          addVar(c->index, c->variable);
          new_vars.push_back(static_cast<int>(c->index));
          break;
        case GraphChange::Kind::RemoveVariable: {
          const Var& r = var(c->index);
          for (int t = 0; r.row >= 0 && t < r.dim; ++t) deleted_rows.push_back(r.row + t);
          removeVar(c->index);
          break;
        }
        case GraphChange::Kind::AddFactor:
          new_factors.push_back(addFactor(c->factor));
          break;
        case GraphChange::Kind::RemoveFactor: {
          const auto it = factor_of.find(c->factor.id);
          if (it == factor_of.end())
            throw std::logic_error("IncrementalFactorization: unknown factor removed");
          const Held& h = factors[it->second];
          if (!h.added) {
            downs.push_back(pieceOf(h));
            addToH(h, -1.0);
          }
          removeFactor(it->second);
          break;
        }
      }
    }
    seq = graph.changeCount();
    dying_count = 0;  // every dying variable is gone now
    dead_rows += static_cast<int>(deleted_rows.size());
    for (int r : deleted_rows) {  // the rows leave H: identity
      owner[r] = -1;
      Hx[Hp[r + 1] - 1] = 1.0;
      g[r] = 0;
      est[r] = 0;
    }
    // New variables still there: their value now is their linearization point; rows from the
    // spares, or a fresh ordering when those ran out.
    std::vector<int> identity_rows;
    bool room = true;
    for (int v : new_vars) {
      Var& r = vars[v];
      if (!r.alive || r.row >= 0) continue;
      r.lin = valueIn(graph, r.key);
      if (next_row + r.dim > capacity()) {
        room = false;
        continue;
      }
      r.row = next_row;
      next_row += r.dim;
      for (int t = 0; t < r.dim; ++t) {
        owner[r.row + t] = v;
        identity_rows.push_back(r.row + t);
      }
      g.segment(r.row, r.dim).setZero();
      est.segment(r.row, r.dim) = r.lin.head(r.dim);
    }
    std::vector<int> added;
    for (int k : new_factors) {
      Held& h = factors[k];
      if (!h.alive || !h.added) continue;
      h.lin = linearizeHeld(h);
      h.added = false;
      added.push_back(k);
    }
    if (!room) {
      reorder();
      return;
    }
    if (!extendPattern(first_new_row, added)) {
      // A new factor ties two variables H had no entry for: the pattern anew (values too).
      buildPattern();
    } else {
      for (int k : added) addToH(factors[k], 1.0);
    }
    for (int k : added) ups.push_back(pieceOf(factors[k]));
    fold(identity_rows);
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
      Var& r = vars[index[k]];
      const auto value = x.segment(starts[k], r.dim);
      if (value != est.segment(r.row, r.dim)) {
        est.segment(r.row, r.dim) = value;
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

  /// Variables whose estimate left their linearization point by more than `threshold` take the
  /// estimate as their new linearization point; their factors are relinearized.
  void relinearizeMoved(double threshold) {
    std::vector<int> moved;
    for (int v = 0; v < static_cast<int>(vars.size()); ++v) {
      Var& r = vars[v];
      if (!r.alive) continue;
      if (maxAbsDifference(r.dim, est.data() + r.row, r.lin.data()) > threshold) {
        r.lin.head(r.dim) = est.segment(r.row, r.dim);
        moved.push_back(v);
      }
    }
    stats.moved_variables += moved.size();
    relinearize(moved);
  }

  /// est = lin + dx with dx = -H^-1 g (the minimizer of the linearized cost); returns the
  /// largest change of est.
  double solveEstimate() {
    const Eigen::VectorXd dx = -chol.solve(g);
    double change = 0;
    for (const Var& r : vars) {
      if (!r.alive) continue;
      Eigen::Vector3d x = r.lin;
      x.head(r.dim) += dx.segment(r.row, r.dim);
      if (r.key.kind == VariableKey::Kind::Pose) x.z() = wrapAngle(x.z());
      change = std::max(change, maxAbsDifference(r.dim, x.data(), est.data() + r.row));
      est.segment(r.row, r.dim) = x.head(r.dim);
    }
    return change;
  }

  /// `est` into the graph (in its column order).
  void writeEstimate(FactorGraph& graph) {
    Eigen::VectorXd x(graph.dim());
    int c = 0;
    for (VariableIndex v : graph.variableIndices()) {
      const Var& r = vars[v];
      x.segment(c, r.dim) = est.segment(r.row, r.dim);
      c += r.dim;
    }
    graph.setValues(x);
    values_version = graph.valuesVersion();
  }
};

IncrementalFactorization::IncrementalFactorization(double reorder_fill_ratio)
    : s_(std::make_unique<State>(reorder_fill_ratio)) {}

IncrementalFactorization::~IncrementalFactorization() = default;

IncrementalFactorization::IncrementalFactorization(const IncrementalFactorization& o)
    : s_(std::make_unique<State>(o.s_->reorder_fill_ratio)) {
  State& s = *s_;
  const State& t = *o.s_;
  s.vars = t.vars;
  s.factors = t.factors;
  s.free_factors = t.free_factors;
  s.factor_of = t.factor_of;
  s.factor_count = t.factor_count;
  s.owner = t.owner;
  s.next_row = t.next_row;
  s.Hp = t.Hp;
  s.Hi = t.Hi;
  s.Hx = t.Hx;
  s.dead_rows = t.dead_rows;
  s.g = t.g;
  s.est = t.est;
  s.chi2 = t.chi2;
  s.chol = t.chol.copy();
  s.built = t.built;
  s.lineage = t.lineage;
  s.seq = t.seq;
  s.values_version = t.values_version;
  s.fresh_fill = t.fresh_fill;
  s.fresh_flops = t.fresh_flops;
  s.fresh_depth = t.fresh_depth;
  s.refresh_flops = t.refresh_flops;
  s.stale_pattern = t.stale_pattern;
  s.path_cost = t.path_cost;
  s.stats = t.stats;
}

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
    if (s.degraded(kQueryFillRatio) || s.meanDepth() > kQueryFillRatio * s.fresh_depth) s.reorder();
  }
  if (!s.map_valid || s.map_variables != graph.variablesVersion()) {
    // The graph's columns (poses by step, then landmarks by id) to the rows of H.
    std::vector<int> map;
    map.reserve(static_cast<std::size_t>(graph.dim()));
    for (VariableIndex v : graph.variableIndices()) {
      const State::Var& r = s.vars[v];
      for (int t = 0; t < r.dim; ++t) map.push_back(r.row + t);
    }
    s.chol.setColumnMap(std::move(map));
    s.map_valid = true;
    s.map_variables = graph.variablesVersion();
  }
  return s.chol;
}

SolveReport IncrementalFactorization::iterate(FactorGraph& graph, const IncrementalStep& step) {
  State& s = *s_;
  s.sync(graph);
  SolveReport rep;
  const bool exact = step.relinearize_threshold <= 0;
  for (int it = 0; it < step.max_iterations; ++it) {
    if (step.stop_on_request) Cancellation::check();
    s.relinearizeMoved(step.relinearize_threshold);
    if (it == 0) rep.initial_chi2 = s.chi2;
    // With every variable at its linearization point chi2 is the cost of the estimate: a step
    // that raised it beyond rounding (diverging, far from the optimum) is undone, and it stops.
    if (exact && it > 0 && s.chi2 > rep.final_chi2 * (1 + 1e-9)) {
      s.est = s.est_before;
      s.relinearizeMoved(0);
      s.writeEstimate(graph);
      break;
    }
    rep.final_chi2 = s.chi2;
    if (exact) s.est_before = s.est;
    const double change = s.solveEstimate();
    s.writeEstimate(graph);
    rep.iterations = it + 1;
    rep.last_step_norm = change;
    if (change < step.step_tolerance) {
      rep.converged = true;
      break;
    }
    if (exact && step.relative_chi2_tolerance > 0 && it > 0 &&
        rep.initial_chi2 - s.chi2 <= step.relative_chi2_tolerance * rep.initial_chi2) {
      rep.converged = true;
      break;
    }
  }
  return rep;
}

Eigen::VectorXd IncrementalFactorization::step(const FactorGraph& graph) {
  State& s = *s_;
  s.sync(graph);
  const Eigen::VectorXd dx = -s.chol.solve(s.g);
  Eigen::VectorXd out(graph.dim());
  int c = 0;
  for (VariableIndex v : graph.variableIndices()) {
    const State::Var& r = s.vars[v];
    out.segment(c, r.dim) = dx.segment(r.row, r.dim);
    c += r.dim;
  }
  return out;
}

Eigen::VectorXd IncrementalFactorization::linearizationPoint(const FactorGraph& graph) {
  State& s = *s_;
  s.sync(graph);
  Eigen::VectorXd out(graph.dim());
  int c = 0;
  for (VariableIndex v : graph.variableIndices()) {
    const State::Var& r = s.vars[v];
    out.segment(c, r.dim) = r.lin.head(r.dim);
    c += r.dim;
  }
  return out;
}

double IncrementalFactorization::chi2() const { return s_->chi2; }

const IncrementalStats& IncrementalFactorization::stats() const { return s_->stats; }

}  // namespace budget_slam::graph
