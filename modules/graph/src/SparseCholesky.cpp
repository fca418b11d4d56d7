#include "budget_slam/graph/SparseCholesky.h"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "GramKernel.h"

namespace budget_slam::graph {

namespace {
using SpMat = Eigen::SparseMatrix<double>;

/// Eigen's wrapper with access to CHOLMOD's factor (a protected member of CholmodBase).
class Cholmod : public Eigen::CholmodDecomposition<SpMat, Eigen::Lower> {
 public:
  cholmod_factor* factor() const { return m_cholmodFactor; }
};
}  // namespace

struct SparseCholesky::Impl {
  Cholmod chol;
  bool ok = false;
  bool analysed = false;
  std::uint64_t version = 0;
  int n = 0;

  // The factor as simplicial LL^T CSC columns for the partial inverses, set up on first use after
  // each factorization: column k at Li/Lx[Lp[k] .. Lp[k] + Lnz[k] - 1], diagonal first. They point
  // into CHOLMOD's own simplicial LL^T factor (no copy), or into a copy (Lp_s ...) when CHOLMOD
  // kept a supernodal factor. Plus the permutation and the elimination tree.
  mutable bool have_L = false;
  mutable const int *Lp = nullptr, *Lnz = nullptr, *Li = nullptr;
  mutable const double* Lx = nullptr;
  mutable std::size_t nnz = 0;
  mutable std::vector<int> Lp_s, Lnz_s, Li_s, perm, iperm, parent;
  mutable std::vector<double> Lx_s;

  void extractL() const {
    if (have_L) return;
    cholmod_factor* F = chol.factor();
    if (F->is_super && F->is_ll && F->xtype == CHOLMOD_REAL) {
      extractSupernodal(*F);
    } else {
      // A simplicial LDL^T (CHOLMOD's usual choice on these sparse graphs): converted to LL^T in
      // place, O(nnz), then read directly. Done here, on the first partial inverse, rather than
      // in factorize(): callers that only solve or take log-determinants (the naive reference)
      // never pay for it. solve() and logDet() handle either form.
      if (!F->is_ll || !F->is_monotonic || F->xtype != CHOLMOD_REAL) {
        cholmod_common& c = const_cast<Cholmod&>(chol).cholmod();
        if (!cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/1, /*to_super=*/0, /*to_packed=*/1,
                                   /*to_monotonic=*/1, F, &c))
          throw std::runtime_error("CHOLMOD: cannot convert the factor");
      }
      viewSimplicial(*F);
    }
    iperm.resize(n);
    for (int k = 0; k < n; ++k) iperm[perm[k]] = k;
    have_L = true;
  }

  /// CHOLMOD's simplicial LL^T factor read in place: its p, nz, i, x arrays are already CSC
  /// columns with the diagonal first (possibly with slack between columns, hence nz).
  void viewSimplicial(const cholmod_factor& F) const {
    Lp = static_cast<const int*>(F.p);
    Lnz = static_cast<const int*>(F.nz);
    Li = static_cast<const int*>(F.i);
    Lx = static_cast<const double*>(F.x);
    const int* P = static_cast<const int*>(F.Perm);
    nnz = 0;
    parent.assign(n, -1);
    perm.resize(n);
    for (int k = 0; k < n; ++k) {
      nnz += Lnz[k];
      // The etree parent is the smallest row below the diagonal.
      for (int q = Lp[k] + 1; q < Lp[k] + Lnz[k]; ++q)
        if (parent[k] == -1 || Li[q] < parent[k]) parent[k] = Li[q];
      perm[k] = P ? P[k] : k;
    }
  }

  /// The CSC columns straight from a supernodal LL^T factor: supernode s holds columns
  /// super[s] .. super[s+1]-1 as a dense column-major block (rows pi[s] .. pi[s+1]-1 of s[], its
  /// row indices, ascending with the supernode's own columns first); column j's entries are the
  /// block's column from its diagonal down. No copy or conversion by CHOLMOD.
  void extractSupernodal(const cholmod_factor& F) const {
    const int* super = static_cast<const int*>(F.super);
    const int* pi = static_cast<const int*>(F.pi);
    const int* px = static_cast<const int*>(F.px);
    const int* srows = static_cast<const int*>(F.s);
    const double* x = static_cast<const double*>(F.x);
    const int* P = static_cast<const int*>(F.Perm);
    Lp_s.assign(n + 1, 0);
    Lnz_s.assign(n, 0);
    for (std::size_t sn = 0; sn < F.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      for (int k = k1; k < k2; ++k) Lnz_s[k] = nrows - (k - k1);
    }
    for (int k = 0; k < n; ++k) Lp_s[k + 1] = Lp_s[k] + Lnz_s[k];
    Li_s.resize(Lp_s[n]);
    Lx_s.resize(Lp_s[n]);
    parent.assign(n, -1);
    for (std::size_t sn = 0; sn < F.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      const int* rows = srows + pi[sn];
      const double* blk = x + px[sn];
      for (int k = k1; k < k2; ++k) {
        const int c = k - k1;
        std::copy(rows + c, rows + nrows, Li_s.begin() + Lp_s[k]);
        std::copy(blk + static_cast<std::size_t>(c) * nrows + c,
                  blk + static_cast<std::size_t>(c + 1) * nrows, Lx_s.begin() + Lp_s[k]);
        if (c + 1 < nrows) parent[k] = rows[c + 1];  // rows ascending: the first below diagonal
      }
    }
    perm.resize(n);
    for (int k = 0; k < n; ++k) perm[k] = P ? P[k] : k;
    Lp = Lp_s.data();
    Lnz = Lnz_s.data();
    Li = Li_s.data();
    Lx = Lx_s.data();
    nnz = Lp_s[n];
  }

  // Postorder of the elimination tree (children before parents, each subtree a contiguous
  // interval [first[k], post[k]]), built on first use after each factorization.
  mutable bool have_post = false;
  mutable std::vector<int> post, first;

  void postorder() const {
    extractL();
    if (have_post) return;
    std::vector<int> head(n, -1), next(n, -1), stack;
    for (int k = n - 1; k >= 0; --k)  // children lists, ascending
      if (parent[k] != -1) {
        next[k] = head[parent[k]];
        head[parent[k]] = k;
      }
    post.assign(n, 0);
    first.assign(n, 0);
    int counter = 0;
    for (int root = 0; root < n; ++root) {
      if (parent[root] != -1) continue;
      stack.push_back(root);
      while (!stack.empty()) {
        const int k = stack.back();
        if (head[k] != -1) {  // descend into the next unvisited child
          const int c = head[k];
          head[k] = next[c];
          stack.push_back(c);
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
    findDenseTail();
    have_post = true;
  }

  // The dense tail of the factor: the last t columns of L when they form a full lower triangle
  // (the root separator, which the fill-reducing ordering leaves for the end; t = 104 of 21206
  // on the full Victoria Park graph). Every etree path of a connected graph ends in it, so the
  // partial inverses spend most of their flops there (about 70% for the information gain on
  // Victoria Park); it is kept as a dense t x t block so those parts run as dense blocked
  // kernels (triangular solve and rank-t update) instead of row-by-row sparse updates.
  static constexpr int kMinDenseTail = 16;  ///< below this the sparse kernels are as good
  mutable int tail = 0;
  mutable Eigen::MatrixXd Ltail;  ///< L_TT, lower triangle, column-major

  void findDenseTail() const {
    int t = 0;
    while (t < n && Lnz[n - 1 - t] == t + 1) ++t;  // column k has all rows k .. n-1
    tail = t >= kMinDenseTail ? t : 0;
    Ltail.setZero(tail, tail);
    const int k0 = n - tail;
    for (int k = k0; k < n; ++k)
      for (int q = Lp[k]; q < Lp[k] + Lnz[k]; ++q) Ltail(Li[q] - k0, k - k0) = Lx[q];
  }

  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // Workspaces of the partial inverses, reused between calls and between factorizations: fresh
  // multi-megabyte buffers cost more in page faults than the arithmetic, and callers build a new
  // SparseCholesky per query (factorizeAtEstimate). One per thread, so queries on different
  // threads do not share them; a returned view is valid until the thread's next query.
  struct Workspace {
    std::vector<char> seen;
    std::vector<int> local, start, pos, nodes, lo, hi, range;
    std::vector<const double*> ptr;
    std::vector<std::uint64_t> bits;  ///< all zero between calls
    std::vector<double> x, g;
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
    std::vector<int> nodes;
    w.seen.assign(n, 0);
    std::vector<char>& seen = w.seen;
    for (int c : S) {
      if (c < 0 || c >= n) throw std::out_of_range("SparseCholesky: index out of range");
      for (int k = iperm[c]; k != -1 && !seen[k]; k = parent[k]) {
        seen[k] = 1;
        nodes.push_back(k);
      }
    }
    std::sort(nodes.begin(), nodes.end());
    w.local.resize(n);
    std::vector<int>& local = w.local;
    for (std::size_t a = 0; a < nodes.size(); ++a) local[nodes[a]] = static_cast<int>(a);
    const Eigen::Index cols = R ? R->cols() : static_cast<Eigen::Index>(S.size());
    const std::size_t size = nodes.size() * static_cast<std::size_t>(cols);
    if (w.x.size() < size) w.x.resize(size);
    std::fill(w.x.begin(), w.x.begin() + size, 0.0);
    Eigen::Map<RowMat> X(w.x.data(), nodes.size(), cols);
    for (std::size_t j = 0; j < S.size(); ++j) {
      if (R)
        X.row(local[iperm[S[j]]]) += R->row(j);
      else
        X(local[iperm[S[j]]], j) = 1.0;
    }
    // The path's columns of L on local row numbers, for the substitution kernel.
    std::vector<int> start(nodes.size() + 1, 0), rows;
    std::vector<double> vals;
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      const int k = nodes[a];
      for (int q = Lp[k]; q < Lp[k] + Lnz[k]; ++q) {
        rows.push_back(q == Lp[k] ? static_cast<int>(a) : local[Li[q]]);
        vals.push_back(Lx[q]);
      }
      start[a + 1] = static_cast<int>(rows.size());
    }
    detail::forwardSubstitute(X.data(), nodes.size(), X.cols(), start.data(), rows.data(),
                              vals.data());
    return X;
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {
  // LL^T or LDL^T, simplicial or supernodal: CHOLMOD's choice. Orderings: CHOLMOD's default
  // strategy (AMD, then METIS/NESDIS when AMD gives much fill).
  impl_->chol.setMode(Eigen::CholmodAuto);
  // A singular H is reported by factorize()'s result, not printed on stdout.
  impl_->chol.cholmod().print = 0;
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::factorize(const SpMat& H, std::uint64_t pattern_version) {
  Impl& m = *impl_;
  m.have_L = false;
  m.n = static_cast<int>(H.rows());
  if (!m.analysed || pattern_version == 0 || pattern_version != m.version) {
    m.chol.analyzePattern(H);
    m.analysed = true;
    m.version = pattern_version;
  }
  m.chol.factorize(H);
  m.have_post = false;
  m.ok = m.chol.info() == Eigen::Success;
  if (!m.ok) m.analysed = false;
  return m.ok;
}

bool SparseCholesky::ok() const { return impl_->ok; }
int SparseCholesky::size() const { return impl_->n; }

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  return impl_->chol.solve(b);
}

double SparseCholesky::logDet() const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  return impl_->chol.logDeterminant();
}

std::size_t SparseCholesky::factorNonZeros() const {
  impl_->extractL();
  return impl_->nnz;
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
    for (int t = 0; t < c.n; ++t) {
      if (c.idx[t] < 0 || c.idx[t] >= m.n)
        throw std::out_of_range("SparseCholesky: index out of range");
      s = std::min(s, m.iperm[c.idx[t]]);
    }
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
  for (int k = m.n - m.tail; k < m.n; ++k) {
    mark(k);
    lowest = std::min(lowest, k);
  }
  for (std::size_t word = static_cast<std::size_t>(lowest) >> 6; word < bits.size(); ++word) {
    for (std::uint64_t b = bits[word]; b != 0; b &= b - 1)
      nodes.push_back(static_cast<int>(word * 64) + __builtin_ctzll(b));
    bits[word] = 0;
  }
  w.local.resize(m.n);
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
      X[static_cast<std::size_t>(w.local[m.iperm[cols[j].idx[t]]]) * ld + pos[j]] += cols[j].val[t];
  detail::forwardSubstitutePath(X, ld, nodes.data(), ms, m.Lp, m.Lnz, m.Li, m.Lx, w.local.data(),
                                lo.data(), hi.data());
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
