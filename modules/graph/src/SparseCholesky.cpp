#include "budget_slam/graph/SparseCholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "GramKernel.h"

namespace budget_slam::graph {

namespace {
using SpMat = Eigen::SparseMatrix<double>;

/// A CHOLMOD view (no copy) of a compressed-column matrix, nrow x ncol: `p`, `i` as CHOLMOD's
/// column pointers and row indices (rows ascending), `x` the values (null for a pattern,
/// CHOLMOD_PATTERN); `stype` -1 / 1: symmetric with only the lower / upper triangle read, 0:
/// unsymmetric.
cholmod_sparse compressedView(std::size_t nrow, std::size_t ncol, std::size_t nonzeros,
                              const int* p, const int* i, const double* x, int stype) {
  cholmod_sparse A{};
  A.nrow = nrow;
  A.ncol = ncol;
  A.nzmax = nonzeros;
  A.p = const_cast<int*>(p);
  A.i = const_cast<int*>(i);
  A.x = const_cast<double*>(x);
  A.stype = stype;
  A.itype = CHOLMOD_INT;
  A.xtype = x ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

cholmod_sparse lowerTriangleView(std::size_t n, std::size_t nonzeros, const int* p, const int* i,
                                 const double* x) {
  return compressedView(n, n, nonzeros, p, i, x, -1);
}

/// An upper triangle as a CHOLMOD matrix (a view, no copy).
cholmod_sparse upperView(const SparseCholesky::UpperTriangle& H) {
  const std::size_t n = static_cast<std::size_t>(H.n);
  return compressedView(n, n, static_cast<std::size_t>(H.p[H.n]), H.p, H.i, H.x, 1);
}

/// H's lower triangle as a CHOLMOD matrix (a view, no copy; H must be compressed).
cholmod_sparse viewLower(const SpMat& H) {
  if (!H.isCompressed()) throw std::invalid_argument("SparseCholesky: H is not compressed");
  return lowerTriangleView(static_cast<std::size_t>(H.rows()),
                           static_cast<std::size_t>(H.nonZeros()), H.outerIndexPtr(),
                           H.innerIndexPtr(), H.valuePtr());
}
}  // namespace

struct SparseCholesky::Impl {
  cholmod_common c{};
  cholmod_factor* F = nullptr;
  bool ok = false;
  bool analysed = false;  ///< F holds an analysis factorize() may reuse
  std::uint64_t version = 0;
  int n = 0;

  Impl() {
    cholmod_start(&c);
    c.print = 0;  // a singular H is reported by the result, not printed on stdout
  }
  ~Impl() {
    if (F) cholmod_free_factor(&F, &c);
    cholmod_finish(&c);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  // The factor as simplicial CSC columns for the partial inverses, set up on first use after
  // each change: column k at Li/Lx[Lp[k] .. Lp[k] + Lnz[k] - 1], diagonal first, rows ascending.
  // They point into CHOLMOD's own simplicial factor (no copy; `ldl`: a unit L D L^T with D on
  // the diagonal, as CHOLMOD's simplicial factorization and its update routines keep it), or
  // into a copy (Lp_s ...) when CHOLMOD kept a supernodal L L^T. The permutation and its inverse
  // change only with a new analysis.
  mutable bool have_L = false;
  mutable bool ldl = false;
  mutable const int *Lp = nullptr, *Lnz = nullptr, *Li = nullptr;
  mutable const double* Lx = nullptr;
  mutable std::vector<int> Lp_s, Lnz_s, Li_s, perm, iperm;
  mutable std::vector<double> Lx_s;
  mutable bool have_perm = false;
  // The queries' column space: external column c is row colmap[c] of the factorized matrix
  // (identity when empty); colpos[c] is its position in the factor, rebuilt with the permutation.
  std::vector<int> colmap;
  mutable std::vector<int> colpos;
  mutable bool have_colpos = false;
  double analysis_flops = 0;     ///< CHOLMOD's flop count of the last analysis
  double analysis_nonzeros = 0;  ///< nnz(L) predicted by the last analysis

  int columns() const { return colmap.empty() ? n : static_cast<int>(colmap.size()); }
  /// Position in the factor of external column c; throws std::out_of_range outside.
  int positionOf(int c) const {
    if (c < 0 || c >= static_cast<int>(colpos.size()))
      throw std::out_of_range("SparseCholesky: index out of range");
    return colpos[c];
  }

  /// The etree parent of column k: the first row below the diagonal (-1 at a root).
  int parentOf(int k) const { return Lnz[k] > 1 ? Li[Lp[k] + 1] : -1; }

  void extractL() const {
    if (have_L) return;
    if (!F || !ok) throw std::logic_error("SparseCholesky: no factorization");
    if (F->is_super) {
      extractSupernodal(*F);
      ldl = false;
    } else {
      Lp = static_cast<const int*>(F->p);
      Lnz = static_cast<const int*>(F->nz);
      Li = static_cast<const int*>(F->i);
      Lx = static_cast<const double*>(F->x);
      ldl = !F->is_ll;
    }
    if (!have_perm) {
      const int* P = static_cast<const int*>(F->Perm);
      perm.resize(n);
      iperm.resize(n);
      for (int k = 0; k < n; ++k) perm[k] = P ? P[k] : k;
      for (int k = 0; k < n; ++k) iperm[perm[k]] = k;
      have_perm = true;
      have_colpos = false;
    }
    if (!have_colpos) {
      if (colmap.empty()) {
        colpos = iperm;
      } else {
        colpos.resize(colmap.size());
        for (std::size_t c = 0; c < colmap.size(); ++c) colpos[c] = iperm.at(colmap[c]);
      }
      have_colpos = true;
    }
    have_L = true;
  }

  /// The CSC columns straight from a supernodal LL^T factor: supernode s holds columns
  /// super[s] .. super[s+1]-1 as a dense column-major block (rows pi[s] .. pi[s+1]-1 of s[], its
  /// row indices, ascending with the supernode's own columns first); column j's entries are the
  /// block's column from its diagonal down. No copy or conversion by CHOLMOD.
  void extractSupernodal(const cholmod_factor& S) const {
    const int* super = static_cast<const int*>(S.super);
    const int* pi = static_cast<const int*>(S.pi);
    const int* px = static_cast<const int*>(S.px);
    const int* srows = static_cast<const int*>(S.s);
    const double* x = static_cast<const double*>(S.x);
    Lp_s.assign(n + 1, 0);
    Lnz_s.assign(n, 0);
    for (std::size_t sn = 0; sn < S.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      for (int k = k1; k < k2; ++k) Lnz_s[k] = nrows - (k - k1);
    }
    for (int k = 0; k < n; ++k) Lp_s[k + 1] = Lp_s[k] + Lnz_s[k];
    Li_s.resize(Lp_s[n]);
    Lx_s.resize(Lp_s[n]);
    for (std::size_t sn = 0; sn < S.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      const int* rows = srows + pi[sn];
      const double* blk = x + px[sn];
      for (int k = k1; k < k2; ++k) {
        const int c0 = k - k1;
        std::copy(rows + c0, rows + nrows, Li_s.begin() + Lp_s[k]);
        std::copy(blk + static_cast<std::size_t>(c0) * nrows + c0,
                  blk + static_cast<std::size_t>(c0 + 1) * nrows, Lx_s.begin() + Lp_s[k]);
      }
    }
    Lp = Lp_s.data();
    Lnz = Lnz_s.data();
    Li = Li_s.data();
    Lx = Lx_s.data();
  }

  /// The L L^T factor's diagonal entry and off-diagonal entry q of column k.
  double diagLL(int k) const { return ldl ? std::sqrt(Lx[Lp[k]]) : Lx[Lp[k]]; }

  // Postorder of the elimination tree (children before parents, each subtree a contiguous
  // interval [first[k], post[k]]), built on first use after each change.
  mutable bool have_post = false;
  mutable std::vector<int> parent, post, first;

  void postorder() const {
    extractL();
    if (have_post) return;
    parent.resize(n);
    for (int k = 0; k < n; ++k) parent[k] = parentOf(k);
    std::vector<int> head(n, -1), next(n, -1), stack;
    for (int k = n - 1; k >= 0; --k)  // children lists, ascending
      if (parent[k] != -1) {
        next[k] = head[parent[k]];
        head[parent[k]] = k;
      }
    std::vector<char> has_child(n, 0);
    for (int k = 0; k < n; ++k)
      if (parent[k] != -1) has_child[parent[k]] = 1;
    post.assign(n, 0);
    first.assign(n, 0);
    int counter = 0;
    for (int root = 0; root < n; ++root) {
      if (parent[root] != -1) continue;
      stack.push_back(root);
      while (!stack.empty()) {
        const int k = stack.back();
        if (head[k] != -1) {  // descend into the next unvisited child
          const int ch = head[k];
          head[k] = next[ch];
          stack.push_back(ch);
          continue;
        }
        stack.pop_back();
        post[k] = counter++;
      }
    }
    // first[k] = smallest postorder number in k's subtree (children come before parents).
    for (int k = 0; k < n; ++k) first[k] = post[k];
    std::vector<int> by_post(n);
    for (int k = 0; k < n; ++k) by_post[post[k]] = k;
    for (int p = 0; p < n; ++p) {
      const int k = by_post[p];
      if (parent[k] != -1) first[parent[k]] = std::min(first[parent[k]], first[k]);
    }
    // The columns at the end that stand alone (spare columns of an incremental factor, identity
    // rows of H: no entry below the diagonal, no child) are not part of any path.
    active_end = n;
    while (active_end > 0 && Lnz[active_end - 1] == 1 && !has_child[active_end - 1]) --active_end;
    findDenseTail();
    have_post = true;
  }

  // The dense tail of the factor: the last t columns of L before the stand-alone ones, kept as a
  // dense t x t block (zero where L has no entry) so that the partial inverses run there as dense
  // blocked kernels (triangular solve and rank-t update) instead of row-by-row sparse updates.
  // Every etree path of a connected graph ends in it: the root separator, which the fill-reducing
  // ordering leaves for the end as a full triangle (t = 104 of 21206 on the full Victoria Park
  // graph, about 70% of the information gain's flops), and in the held factor the variables added
  // after it since its last fresh ordering. The block is the one that saves the most: the sparse
  // kernels' work on its entries, sum nnz, less the dense kernels' on the full triangle, which
  // run about kDenseSpeedup times faster per entry. Any trailing block gives the same numbers:
  // its columns' rows all lie inside it.
  static constexpr int kMinDenseTail = 16;   ///< below this the sparse kernels are as good
  static constexpr int kMaxDenseTail = 512;  ///< bounds the dense block (2 MB)
  static constexpr double kDenseSpeedup = 4;
  mutable int tail = 0;
  mutable int active_end = 0;
  mutable Eigen::MatrixXd Ltail;  ///< L_TT (of L L^T), lower triangle, column-major

  void findDenseTail() const {
    int t = 0;
    double filled = 0, best = 0;
    for (int u = 1; u <= std::min(active_end, kMaxDenseTail); ++u) {
      filled += Lnz[active_end - u];
      const double saved = filled - 0.5 * u * (u + 1.0) / kDenseSpeedup;
      if (saved > best) {
        best = saved;
        t = u;
      }
    }
    tail = t >= kMinDenseTail ? t : 0;
    Ltail.setZero(tail, tail);
    const int k0 = active_end - tail;
    for (int k = k0; k < active_end; ++k) {
      const double d = diagLL(k);
      Ltail(k - k0, k - k0) = d;
      const double scale = ldl ? d : 1.0;
      for (int q = Lp[k] + 1; q < Lp[k] + Lnz[k]; ++q) Ltail(Li[q] - k0, k - k0) = Lx[q] * scale;
    }
  }

  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // Workspaces of the partial inverses, reused between calls and between factorizations: fresh
  // multi-megabyte buffers cost more in page faults than the arithmetic, and callers build a new
  // SparseCholesky per query (factorizeAtEstimate). One per thread, so queries on different
  // threads do not share them; a returned view is valid until the thread's next query. Nothing
  // in them is cleared in O(n) per call: `stamp` marks path nodes with a call counter.
  struct Workspace {
    std::vector<unsigned> stamp;
    unsigned counter = 0;
    std::vector<int> local, start, pos, nodes, lo, hi, range, path_start, path_rows;
    std::vector<const double*> ptr;
    std::vector<std::uint64_t> bits;  ///< all zero between calls
    std::vector<double> x, g, path_vals;
  };
  static Workspace& workspace() {
    thread_local Workspace w;
    return w;
  }

  /// Forward substitution L X = P E_S R restricted to the union of etree paths of S, R being
  /// |S| x r (identity when null). Returns X (rows: the path nodes, ascending), a view of a
  /// workspace valid until the next call.
  Eigen::Map<RowMat> forward(const std::vector<int>& S, const Eigen::MatrixXd* R = nullptr) const {
    extractL();
    Workspace& w = workspace();
    if (w.stamp.size() < static_cast<std::size_t>(n)) w.stamp.resize(n, 0);
    if (w.local.size() < static_cast<std::size_t>(n)) w.local.resize(n);
    if (++w.counter == 0) {  // wrapped: clear once
      std::fill(w.stamp.begin(), w.stamp.end(), 0u);
      w.counter = 1;
    }
    std::vector<int>& nodes = w.nodes;
    nodes.clear();
    for (int col : S) {
      for (int k = positionOf(col); k != -1 && w.stamp[k] != w.counter; k = parentOf(k)) {
        w.stamp[k] = w.counter;
        nodes.push_back(k);
      }
    }
    std::sort(nodes.begin(), nodes.end());
    for (std::size_t a = 0; a < nodes.size(); ++a) w.local[nodes[a]] = static_cast<int>(a);
    const Eigen::Index cols = R ? R->cols() : static_cast<Eigen::Index>(S.size());
    const std::size_t size = nodes.size() * static_cast<std::size_t>(cols);
    if (w.x.size() < size) w.x.resize(size);
    std::fill(w.x.begin(), w.x.begin() + size, 0.0);
    Eigen::Map<RowMat> X(w.x.data(), nodes.size(), cols);
    for (std::size_t j = 0; j < S.size(); ++j) {
      if (R)
        X.row(w.local[colpos[S[j]]]) += R->row(j);
      else
        X(w.local[colpos[S[j]]], j) = 1.0;
    }
    // The path's columns of the L L^T factor on local row numbers, for the substitution kernel.
    w.path_start.assign(nodes.size() + 1, 0);
    w.path_rows.clear();
    w.path_vals.clear();
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      const int k = nodes[a];
      const double d = diagLL(k), scale = ldl ? d : 1.0;
      w.path_rows.push_back(static_cast<int>(a));
      w.path_vals.push_back(d);
      for (int q = Lp[k] + 1; q < Lp[k] + Lnz[k]; ++q) {
        w.path_rows.push_back(w.local[Li[q]]);
        w.path_vals.push_back(Lx[q] * scale);
      }
      w.path_start[a + 1] = static_cast<int>(w.path_rows.size());
    }
    detail::forwardSubstitute(X.data(), nodes.size(), X.cols(), w.path_start.data(),
                              w.path_rows.data(), w.path_vals.data());
    return X;
  }

  void invalidate() {
    have_L = false;
    have_post = false;
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

SparseCholesky SparseCholesky::copy() const {
  SparseCholesky out;
  Impl& o = *out.impl_;
  const Impl& m = *impl_;
  if (m.F) {
    o.F = cholmod_copy_factor(m.F, &o.c);
    if (!o.F) throw std::bad_alloc();
  }
  o.ok = m.ok;
  o.analysed = m.analysed;
  o.version = m.version;
  o.n = m.n;
  o.colmap = m.colmap;
  o.analysis_flops = m.analysis_flops;
  o.analysis_nonzeros = m.analysis_nonzeros;
  return out;
}

namespace {
/// AMD on the variable graph (one node per variable, an edge where H has a non-zero block) and
/// the variable order expanded to scalar columns, each variable's columns together. H's blocks
/// are dense, so this is the scalar graph with every variable's columns merged: the same fill
/// AMD finds on the scalar pattern (AMD merges indistinguishable columns itself), for the cost
/// of a pattern with about a ninth of the entries. Returns an empty vector if AMD fails.
std::vector<int> variableAmdOrdering(const SpMat& H, const std::vector<int>& starts,
                                     cholmod_common* c) {
  const int n = static_cast<int>(H.rows());
  const int nv = static_cast<int>(starts.size()) - 1;
  if (nv <= 0 || starts.front() != 0 || starts.back() != n) return {};
  std::vector<int> var_of(static_cast<std::size_t>(n));
  for (int v = 0; v < nv; ++v) {
    if (starts[v + 1] <= starts[v]) return {};
    for (int j = starts[v]; j < starts[v + 1]; ++j) var_of[j] = v;
  }
  // Lower triangle of the variable pattern, CSC, rows sorted, no duplicates.
  std::vector<int> Bp(static_cast<std::size_t>(nv) + 1, 0), Bi, mark(nv, -1);
  Bi.reserve(static_cast<std::size_t>(H.nonZeros()) / 4 + 1);
  const int* Hp = H.outerIndexPtr();
  const int* Hi = H.innerIndexPtr();
  for (int v = 0; v < nv; ++v) {
    const std::size_t first = Bi.size();
    for (int j = starts[v]; j < starts[v + 1]; ++j)
      for (int k = Hp[j]; k < Hp[j + 1]; ++k) {
        const int w = var_of[Hi[k]];
        if (w > v && mark[w] != v) {
          mark[w] = v;
          Bi.push_back(w);
        }
      }
    std::sort(Bi.begin() + static_cast<std::ptrdiff_t>(first), Bi.end());
    Bp[v + 1] = static_cast<int>(Bi.size());
  }
  if (Bi.empty()) Bi.push_back(0);  // a valid pointer for CHOLMOD; nzmax counts none
  cholmod_sparse B =
      lowerTriangleView(static_cast<std::size_t>(nv), static_cast<std::size_t>(Bp[nv]), Bp.data(),
                        Bi.data(), nullptr);
  std::vector<int> pv(static_cast<std::size_t>(nv));
  if (!cholmod_amd(&B, nullptr, 0, pv.data(), c)) return {};
  std::vector<int> perm;
  perm.reserve(static_cast<std::size_t>(n));
  for (int v : pv)
    for (int j = starts[v]; j < starts[v + 1]; ++j) perm.push_back(j);
  return perm;
}
}  // namespace

bool SparseCholesky::factorize(const SpMat& H, std::uint64_t pattern_version,
                               const std::vector<int>* variable_starts) {
  Impl& m = *impl_;
  m.invalidate();
  const int n = static_cast<int>(H.rows());
  cholmod_sparse A = viewLower(H);
  if (!m.analysed || pattern_version == 0 || pattern_version != m.version || n != m.n) {
    if (m.F) cholmod_free_factor(&m.F, &m.c);
    m.c.postorder = 1;
    m.c.supernodal = CHOLMOD_AUTO;
    const std::vector<int> perm =
        variable_starts ? variableAmdOrdering(H, *variable_starts, &m.c) : std::vector<int>();
    if (!perm.empty()) {
      // AMD on the variables, postordered; simplicial or supernodal as the flop count says.
      m.c.nmethods = 1;
      m.c.method[0].ordering = CHOLMOD_GIVEN;
      m.F = cholmod_analyze_p(&A, const_cast<int*>(perm.data()), nullptr, 0, &m.c);
      m.c.nmethods = 0;
      // CHOLMOD's own rule for trying METIS after AMD: much fill and many flops.
      if (m.F && m.c.lnz >= 5.0 * static_cast<double>(H.nonZeros()) && m.c.fl >= 500.0 * m.c.lnz)
        cholmod_free_factor(&m.F, &m.c);
    }
    if (!m.F) {
      // CHOLMOD's default strategy: AMD, then METIS/NESDIS when AMD gives much fill.
      m.c.nmethods = 0;
      m.F = cholmod_analyze(&A, &m.c);
    }
    if (!m.F) throw std::runtime_error("CHOLMOD: analysis failed");
    m.analysed = true;
    m.version = pattern_version;
    m.have_perm = false;
    m.analysis_flops = m.c.fl;
    m.analysis_nonzeros = m.c.lnz;
  }
  m.n = n;
  cholmod_factorize(&A, m.F, &m.c);
  m.ok = m.c.status == CHOLMOD_OK && m.F->minor == m.F->n;
  if (!m.ok) m.analysed = false;
  return m.ok;
}

double SparseCholesky::analysedNonZeros() const { return impl_->analysis_nonzeros; }

double SparseCholesky::analysedFlops() const { return impl_->analysis_flops; }

void SparseCholesky::setColumnMap(std::vector<int> rows) {
  for (int r : rows)
    if (r < 0) throw std::invalid_argument("SparseCholesky: negative row in the column map");
  impl_->colmap = std::move(rows);
  impl_->have_colpos = false;
  impl_->have_L = false;
  impl_->have_post = false;
}

std::vector<int> SparseCholesky::ordering() const {
  impl_->extractL();
  return impl_->perm;
}

bool SparseCholesky::factorizeInOrder(const UpperTriangle& H) {
  Impl& m = *impl_;
  m.invalidate();
  cholmod_sparse A = upperView(H);
  if (m.F) cholmod_free_factor(&m.F, &m.c);
  m.c.nmethods = 1;
  m.c.method[0].ordering = CHOLMOD_NATURAL;
  m.c.postorder = 0;  // the rows as given
  m.c.supernodal = CHOLMOD_SIMPLICIAL;
  m.F = cholmod_analyze(&A, &m.c);
  m.c.nmethods = 0;
  m.c.postorder = 1;
  m.c.supernodal = CHOLMOD_AUTO;
  if (!m.F) throw std::runtime_error("CHOLMOD: analysis failed");
  m.analysed = false;  // factorize() analyses anew
  m.have_perm = false;
  m.analysis_flops = m.c.fl;
  m.analysis_nonzeros = m.c.lnz;
  m.n = H.n;
  cholmod_factorize(&A, m.F, &m.c);
  m.ok = m.c.status == CHOLMOD_OK && m.F->minor == m.F->n;
  return m.ok;
}

bool SparseCholesky::refactorizeInOrder(const UpperTriangle& H) {
  Impl& m = *impl_;
  if (!m.F || H.n != m.n || m.F->is_super || m.F->ordering != CHOLMOD_NATURAL)
    throw std::logic_error("SparseCholesky: refactorizeInOrder without factorizeInOrder");
  m.invalidate();
  cholmod_sparse A = upperView(H);
  cholmod_factorize(&A, m.F, &m.c);
  m.ok = m.c.status == CHOLMOD_OK && m.F->minor == m.F->n;
  return m.ok;
}

bool SparseCholesky::refactorizeTrailing(const UpperTriangle& H, int first) {
  Impl& m = *impl_;
  if (!m.F || H.n != m.n || m.F->is_super || m.F->ordering != CHOLMOD_NATURAL)
    throw std::logic_error("SparseCholesky: refactorizeTrailing without factorizeInOrder");
  if (first <= 0) return refactorizeInOrder(H);
  if (first >= H.n) return m.ok;
  m.invalidate();
  cholmod_factor& L = *m.F;
  int* Lp = static_cast<int*>(L.p);
  int* Lnz = static_cast<int*>(L.nz);
  const int* Li = static_cast<const int*>(L.i);
  // Rows from `first` on are computed again: every column keeps only its rows above `first`
  // (rows ascending in each column: the diagonal, then the rows below it), the trailing
  // columns only their diagonal. cholmod_rowfac then computes rows first .. n-1 from the
  // leading rows, which stay (their columns of H did not change).
  for (int j = 0; j < first; ++j) {
    const int* b = Li + Lp[j];
    const int nz = Lnz[j];
    if (nz > 1 && b[nz - 1] >= first)
      Lnz[j] = static_cast<int>(std::lower_bound(b + 1, b + nz, first) - b);
  }
  for (int j = first; j < H.n; ++j) Lnz[j] = 1;
  L.minor = static_cast<std::size_t>(H.n);
  cholmod_sparse A = upperView(H);
  double beta[2] = {0, 0};
  const int ok = cholmod_rowfac(&A, nullptr, beta, static_cast<std::size_t>(first),
                                static_cast<std::size_t>(H.n), m.F, &m.c);
  m.ok = ok && m.c.status == CHOLMOD_OK && m.F->minor == m.F->n;
  return m.ok;
}

std::vector<int> SparseCholesky::orderNodes(int n, const std::vector<int>& p,
                                            const std::vector<int>& i,
                                            const std::vector<int>* group) {
  Impl& m = *impl_;
  if (n <= 0) return {};
  if (static_cast<int>(p.size()) != n + 1)
    throw std::invalid_argument("SparseCholesky: node pattern of the wrong size");
  // Column c's rows r < c, with the diagonal added (CHOLMOD's analysis wants it): a pattern.
  std::vector<int> cp(static_cast<std::size_t>(n) + 1, 0), ci;
  ci.reserve(i.size() + static_cast<std::size_t>(n));
  for (int c = 0; c < n; ++c) {
    for (int k = p[c]; k < p[c + 1]; ++k) ci.push_back(i[k]);
    ci.push_back(c);
    cp[c + 1] = static_cast<int>(ci.size());
  }
  cholmod_sparse A = compressedView(static_cast<std::size_t>(n), static_cast<std::size_t>(n),
                                    ci.size(), cp.data(), ci.data(), nullptr, 1);
  if (group) {
    if (static_cast<int>(group->size()) != n)
      throw std::invalid_argument("SparseCholesky: node groups of the wrong size");
    std::vector<int> cmember(*group), order(static_cast<std::size_t>(n));
    if (!cholmod_camd(&A, nullptr, 0, cmember.data(), order.data(), &m.c))
      throw std::runtime_error("CHOLMOD: constrained ordering failed");
    return order;
  }
  m.c.nmethods = 1;
  m.c.method[0].ordering = CHOLMOD_AMD;
  m.c.postorder = 1;
  m.c.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* F = cholmod_analyze(&A, &m.c);
  m.c.nmethods = 0;
  m.c.supernodal = CHOLMOD_AUTO;
  if (!F) throw std::runtime_error("CHOLMOD: ordering failed");
  const int* P = static_cast<const int*>(F->Perm);
  std::vector<int> order(P, P + n);
  cholmod_free_factor(&F, &m.c);
  return order;
}

bool SparseCholesky::ok() const { return impl_->ok; }
int SparseCholesky::size() const { return impl_->n; }

bool SparseCholesky::updateInPlace(bool update, const std::vector<int>& p,
                                   const std::vector<int>& i, const std::vector<double>& x) {
  Impl& m = *impl_;
  if (!m.F || m.F->is_super) throw std::logic_error("SparseCholesky: no simplicial factor");
  const std::size_t ncol = p.empty() ? 0 : p.size() - 1;
  if (ncol == 0 || i.empty()) return true;
  cholmod_sparse C = compressedView(static_cast<std::size_t>(m.n), ncol, i.size(), p.data(),
                                    i.data(), x.data(), 0);
  m.invalidate();
  const int ok = cholmod_updown(update ? 1 : 0, &C, m.F, &m.c);
  m.ok = ok && m.c.status == CHOLMOD_OK;
  return m.ok;
}

bool SparseCholesky::deleteRowInPlace(int k) {
  Impl& m = *impl_;
  if (!m.F || m.F->is_super) throw std::logic_error("SparseCholesky: no simplicial factor");
  if (k < 0 || k >= m.n) throw std::out_of_range("SparseCholesky: row out of range");
  m.invalidate();
  const int ok = cholmod_rowdel(static_cast<std::size_t>(k), nullptr, m.F, &m.c);
  m.ok = ok && m.c.status == CHOLMOD_OK;
  return m.ok;
}

bool SparseCholesky::pruneToPattern(const UpperTriangle& H) {
  Impl& m = *impl_;
  if (!m.F || m.F->is_super) throw std::logic_error("SparseCholesky: no simplicial factor");
  cholmod_sparse A = upperView(H);
  m.invalidate();
  const int ok = cholmod_resymbol(&A, nullptr, 0, /*pack=*/0, m.F, &m.c);
  return ok && m.c.status == CHOLMOD_OK;
}

double SparseCholesky::lastFactorizationFlops() const { return impl_->c.rowfacfl; }

cholmod_factor_struct* SparseCholesky::factor() { return impl_->F; }

int SparseCholesky::position(int row) const {
  impl_->extractL();
  return impl_->iperm.at(row);
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
  Impl& m = *impl_;
  if (!m.ok) throw std::logic_error("SparseCholesky: no factorization");
  if (b.size() != m.n) throw std::invalid_argument("SparseCholesky: right-hand side size");
  cholmod_dense B{};
  B.nrow = B.d = static_cast<std::size_t>(m.n);
  B.ncol = 1;
  B.nzmax = B.nrow;
  B.x = const_cast<double*>(b.data());
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, m.F, &B, &m.c);
  if (!X) throw std::runtime_error("CHOLMOD: solve failed");
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(X->x), m.n);
  cholmod_free_dense(&X, &m.c);
  return x;
}

double SparseCholesky::logDet() const {
  const Impl& m = *impl_;
  if (!m.ok) throw std::logic_error("SparseCholesky: no factorization");
  const cholmod_factor& F = *m.F;
  double s = 0;
  if (F.is_super) {
    const int* super = static_cast<const int*>(F.super);
    const int* pi = static_cast<const int*>(F.pi);
    const int* px = static_cast<const int*>(F.px);
    const double* x = static_cast<const double*>(F.x);
    for (std::size_t sn = 0; sn < F.nsuper; ++sn) {
      const int ncols = super[sn + 1] - super[sn], nrows = pi[sn + 1] - pi[sn];
      for (int j = 0; j < ncols; ++j) s += 2.0 * std::log(x[px[sn] + j * nrows + j]);
    }
    return s;
  }
  const int* Lp = static_cast<const int*>(F.p);
  const double* Lx = static_cast<const double*>(F.x);
  for (int k = 0; k < m.n; ++k) s += (F.is_ll ? 2.0 : 1.0) * std::log(Lx[Lp[k]]);
  return s;
}

std::size_t SparseCholesky::factorNonZeros() const {
  impl_->extractL();
  std::size_t nnz = 0;
  for (int k = 0; k < impl_->n; ++k) nnz += static_cast<std::size_t>(impl_->Lnz[k]);
  return nnz;
}

Eigen::MatrixXd SparseCholesky::inverseBlock(const std::vector<int>& S) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  if (S.empty()) return Eigen::MatrixXd(0, 0);
  const auto X = impl_->forward(S);
  return X.transpose() * X;
}

Eigen::MatrixXd SparseCholesky::inverseQuadraticForm(const std::vector<int>& S,
                                                     const Eigen::MatrixXd& W) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  if (W.cols() != static_cast<Eigen::Index>(S.size()))
    throw std::invalid_argument("SparseCholesky: W and S disagree");
  if (S.empty() || W.rows() == 0) return Eigen::MatrixXd::Zero(W.rows(), W.rows());
  const Eigen::Index r = W.rows();
  const Eigen::MatrixXd R = W.transpose();
  const auto X = impl_->forward(S, &R);
  // Y^T Y: lower triangle by the blocked kernel, then mirrored.
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(r, r);
  std::vector<const double*> rows(static_cast<std::size_t>(X.rows()));
  for (Eigen::Index a = 0; a < X.rows(); ++a) rows[a] = X.data() + a * r;
  detail::gramLowerRows(rows.data(), rows.size(), static_cast<std::size_t>(r), G.data(),
                        static_cast<std::size_t>(r), 0);
  return G.selfadjointView<Eigen::Lower>();
}

Eigen::Map<const Eigen::MatrixXd> SparseCholesky::inverseGram(const std::vector<SparseColumn>& cols,
                                                              std::vector<int>* order) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  const Impl& m = *impl_;
  m.postorder();
  Impl::Workspace& w = Impl::workspace();
  const int r = static_cast<int>(cols.size());
  order->resize(r);
  if (r == 0) return Eigen::Map<const Eigen::MatrixXd>(nullptr, 0, 0);
  // First node of each column (the first eliminated of its indices; the others are ancestors).
  std::vector<int>& start_node = w.start;
  start_node.resize(r);
  for (int j = 0; j < r; ++j) {
    const SparseColumn& c = cols[j];
    if (c.n < 1 || c.n > 3) throw std::invalid_argument("SparseCholesky: bad sparse column");
    int s = m.n;
    for (int t = 0; t < c.n; ++t) s = std::min(s, m.positionOf(c.idx[t]));
    start_node[j] = s;
  }
  // Columns sorted by the postorder of their first node: a subtree's columns are contiguous.
  for (int j = 0; j < r; ++j) (*order)[j] = j;
  std::stable_sort(order->begin(), order->end(),
                   [&](int a, int b) { return m.post[start_node[a]] < m.post[start_node[b]]; });
  std::vector<int>& pos = w.pos;
  pos.resize(r);
  for (int p = 0; p < r; ++p) pos[(*order)[p]] = p;
  // The union of the etree paths, ascending: marked in a bitset (clean between calls) and read
  // back word by word, which sorts them for free (a path climbs to ever larger nodes).
  std::vector<int>& nodes = w.nodes;
  nodes.clear();
  std::vector<std::uint64_t>& bits = w.bits;
  bits.resize((static_cast<std::size_t>(m.n) + 63) / 64, 0);
  const auto marked = [&](int k) { return (bits[k >> 6] >> (k & 63)) & 1u; };
  const auto mark = [&](int k) { bits[k >> 6] |= std::uint64_t{1} << (k & 63); };
  int lowest = m.n;
  for (int j = 0; j < r; ++j) {
    lowest = std::min(lowest, start_node[j]);
    for (int k = start_node[j]; k != -1 && !marked(k); k = m.parent[k]) mark(k);
  }
  // The tail's nodes are always rows of X (zero rows where no path passes: Y = L^-1 P R is exact
  // on any superset of the paths), so that the dense kernels see the whole tail.
  for (int k = m.active_end - m.tail; k < m.active_end; ++k) {
    mark(k);
    lowest = std::min(lowest, k);
  }
  for (std::size_t word = static_cast<std::size_t>(lowest) >> 6; word < bits.size(); ++word) {
    for (std::uint64_t b = bits[word]; b != 0; b &= b - 1)
      nodes.push_back(static_cast<int>(word * 64) + __builtin_ctzll(b));
    bits[word] = 0;
  }
  if (w.local.size() < static_cast<std::size_t>(m.n)) w.local.resize(m.n);
  for (std::size_t a = 0; a < nodes.size(); ++a) w.local[nodes[a]] = static_cast<int>(a);
  const std::size_t mm = nodes.size();
  // Each node's columns: those whose first node lies in its subtree, contiguous in `order` (by
  // postorder). Pushed up the paths, children before parents (the etree parent of k is > k).
  std::vector<int>&lo = w.lo, &hi = w.hi;
  lo.assign(mm, r);
  hi.assign(mm, 0);
  for (int p = 0; p < r; ++p) {
    const int a = w.local[start_node[(*order)[p]]];
    lo[a] = std::min(lo[a], p);
    hi[a] = std::max(hi[a], p + 1);
  }
  for (std::size_t a = 0; a < mm; ++a) {
    if (lo[a] >= hi[a]) {  // a tail node no path passes through: no columns
      lo[a] = hi[a] = 0;
      continue;
    }
    const int up = m.parent[nodes[a]];
    if (up == -1) continue;
    const int b = w.local[up];
    lo[b] = std::min(lo[b], lo[a]);
    hi[b] = std::max(hi[b], hi[a]);
  }
  // The dense tail's rows (the last m.tail rows of X) are left to the dense kernels below; the
  // sparse substitution only pushes its updates into them, leaving Z_T = (P R)_T - L_TD Y_D
  // there (D: the other path rows). The dense kernels work on the tail rows' full width (a tail
  // node below a column's first node holds zeros in that column), so those rows are zeroed in
  // full.
  const std::size_t tail = static_cast<std::size_t>(m.tail);
  const std::size_t ms = mm - tail;  // rows done by the sparse kernels
  for (std::size_t a = ms; a < mm; ++a) {
    lo[a] = 0;
    hi[a] = r;
  }
  // X = P R on the path rows (zero outside each row's range is never read), then L^-1.
  const std::size_t ld = static_cast<std::size_t>(r);
  if (w.x.size() < mm * ld) w.x.resize(mm * ld);
  double* X = w.x.data();
  for (std::size_t a = 0; a < mm; ++a) std::fill(X + a * ld + lo[a], X + a * ld + hi[a], 0.0);
  for (int j = 0; j < r; ++j)
    for (int t = 0; t < cols[j].n; ++t)
      X[static_cast<std::size_t>(w.local[m.colpos[cols[j].idx[t]]]) * ld + pos[j]] +=
          cols[j].val[t];
  detail::forwardSubstitutePath(X, ld, nodes.data(), ms, m.Lp, m.Lnz, m.Li, m.Lx, m.ldl,
                                w.local.data(), lo.data(), hi.data());
  // Y^T Y (lower triangle). The full-width rows just before the tail (ancestors of every column,
  // often the chain below the root separator) join the tail's dense rank update; the other rows
  // are grouped by range, one blocked Gram product per group.
  std::size_t mg = ms;
  while (tail > 0 && mg > 0 && lo[mg - 1] == 0 && hi[mg - 1] == r) --mg;
  std::vector<int>& by_range = w.range;
  by_range.resize(mg);
  for (std::size_t a = 0; a < mg; ++a) by_range[a] = static_cast<int>(a);
  std::sort(by_range.begin(), by_range.end(),
            [&](int a, int b) { return lo[a] != lo[b] ? lo[a] < lo[b] : hi[a] < hi[b]; });
  if (w.g.size() < ld * ld) w.g.resize(ld * ld);
  std::fill(w.g.begin(), w.g.begin() + ld * ld, 0.0);
  for (std::size_t g = 0; g < mg;) {
    const int a0 = by_range[g];
    w.ptr.clear();
    std::size_t e = g;
    for (; e < mg && lo[by_range[e]] == lo[a0] && hi[by_range[e]] == hi[a0]; ++e)
      w.ptr.push_back(X + static_cast<std::size_t>(by_range[e]) * ld + lo[a0]);
    if (hi[a0] > lo[a0])
      detail::gramLowerRows(w.ptr.data(), w.ptr.size(), static_cast<std::size_t>(hi[a0] - lo[a0]),
                            w.g.data(), ld, static_cast<std::size_t>(lo[a0]));
    g = e;
  }
  if (tail > 0) {
    // The tail rows: Y_T = L_TT^-1 Z_T (dense triangular solve), then G += Yg^T Yg over them and
    // the full-width rows before them (one dense symmetric rank update). Same arithmetic as the
    // sparse kernels, in Eigen's blocked ones.
    using RowBlock = Eigen::Map<Impl::RowMat, 0, Eigen::OuterStride<>>;
    RowBlock Y(X + ms * ld, static_cast<Eigen::Index>(tail), r, Eigen::OuterStride<>(ld));
    m.Ltail.triangularView<Eigen::Lower>().solveInPlace(Y);
    const RowBlock Yg(X + mg * ld, static_cast<Eigen::Index>(mm - mg), r, Eigen::OuterStride<>(ld));
    Eigen::Map<Eigen::MatrixXd> G(w.g.data(), r, r);
    G.selfadjointView<Eigen::Lower>().rankUpdate(Yg.transpose());
  }
  return Eigen::Map<const Eigen::MatrixXd>(w.g.data(), r, r);
}

std::vector<Eigen::MatrixXd> SparseCholesky::inverseDiagonalBlocks(
    const std::vector<std::vector<int>>& groups) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  std::vector<int> all;
  for (const auto& g : groups) all.insert(all.end(), g.begin(), g.end());
  std::vector<Eigen::MatrixXd> out;
  out.reserve(groups.size());
  if (all.empty()) {
    for (const auto& g : groups) out.emplace_back(g.size(), g.size());
    return out;
  }
  // Repeated indices across groups are fine: each column of X is solved on its own.
  const auto X = impl_->forward(all);
  int c = 0;
  for (const auto& g : groups) {
    const int s = static_cast<int>(g.size());
    out.push_back(X.middleCols(c, s).transpose() * X.middleCols(c, s));
    c += s;
  }
  return out;
}

}  // namespace budget_slam::graph
