#include "budget_slam/graph/SparseCholesky.h"

#include <Eigen/CholmodSupport>
#include <algorithm>
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

  // Simplicial LL^T copy of the factor for the partial inverses, built on first use after each
  // factorization: CSC columns (diagonal first, rows ascending), permutation and etree.
  mutable bool have_L = false;
  mutable std::vector<int> Lp, Lnz, Li, perm, iperm, parent;
  mutable std::vector<double> Lx;

  void extractL() const {
    if (have_L) return;
    const cholmod_factor* S = chol.factor();
    if (S->is_super && S->is_ll && S->xtype == CHOLMOD_REAL) {
      extractSupernodal(*S);
      return;
    }
    cholmod_common& c = const_cast<Cholmod&>(chol).cholmod();
    cholmod_factor* F = cholmod_copy_factor(chol.factor(), &c);
    if (!F || !cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/1, /*to_super=*/0, /*to_packed=*/1,
                                     /*to_monotonic=*/1, F, &c)) {
      if (F) cholmod_free_factor(&F, &c);
      throw std::runtime_error("CHOLMOD: cannot convert the factor");
    }
    const int* p = static_cast<const int*>(F->p);
    const int* nz = static_cast<const int*>(F->nz);
    const int* i = static_cast<const int*>(F->i);
    const double* x = static_cast<const double*>(F->x);
    const int* P = static_cast<const int*>(F->Perm);
    Lp.assign(n + 1, 0);
    Lnz.assign(n, 0);
    for (int k = 0; k < n; ++k) {
      Lnz[k] = nz[k];
      Lp[k + 1] = Lp[k] + nz[k];
    }
    Li.resize(Lp[n]);
    Lx.resize(Lp[n]);
    parent.assign(n, -1);
    perm.resize(n);
    iperm.resize(n);
    for (int k = 0; k < n; ++k) {
      std::copy(i + p[k], i + p[k] + nz[k], Li.begin() + Lp[k]);
      std::copy(x + p[k], x + p[k] + nz[k], Lx.begin() + Lp[k]);
      // The diagonal comes first; the etree parent is the smallest row below it.
      for (int q = p[k] + 1; q < p[k] + nz[k]; ++q)
        if (parent[k] == -1 || i[q] < parent[k]) parent[k] = i[q];
      perm[k] = P ? P[k] : k;
    }
    for (int k = 0; k < n; ++k) iperm[perm[k]] = k;
    cholmod_free_factor(&F, &c);
    have_L = true;
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
    Lp.assign(n + 1, 0);
    Lnz.assign(n, 0);
    for (std::size_t sn = 0; sn < F.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      for (int k = k1; k < k2; ++k) Lnz[k] = nrows - (k - k1);
    }
    for (int k = 0; k < n; ++k) Lp[k + 1] = Lp[k] + Lnz[k];
    Li.resize(Lp[n]);
    Lx.resize(Lp[n]);
    parent.assign(n, -1);
    for (std::size_t sn = 0; sn < F.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
      const int* rows = srows + pi[sn];
      const double* blk = x + px[sn];
      for (int k = k1; k < k2; ++k) {
        const int c = k - k1;
        std::copy(rows + c, rows + nrows, Li.begin() + Lp[k]);
        std::copy(blk + static_cast<std::size_t>(c) * nrows + c,
                  blk + static_cast<std::size_t>(c + 1) * nrows, Lx.begin() + Lp[k]);
        if (c + 1 < nrows) parent[k] = rows[c + 1];  // rows ascending: the first below diagonal
      }
    }
    perm.resize(n);
    iperm.resize(n);
    for (int k = 0; k < n; ++k) perm[k] = P ? P[k] : k;
    for (int k = 0; k < n; ++k) iperm[perm[k]] = k;
    have_L = true;
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
    have_post = true;
  }

  // Workspaces reused between calls: fresh multi-megabyte buffers per landmark cost more in
  // page faults than the arithmetic (not thread-safe; one backend per thread).
  mutable std::vector<char> seen_ws;
  mutable std::vector<int> local_ws;
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  mutable std::vector<double> x_ws;
  // inverseGram's workspaces (kept: fresh multi-megabyte buffers per landmark page-fault).
  mutable std::vector<int> start_ws, order_ws, pos_ws, post_ws, nodes_ws, lo_ws, hi_ws, range_ws;
  mutable std::vector<const double*> ptr_ws;
  mutable std::vector<char> mark_ws;  ///< all zero between calls
  mutable std::vector<double> g_ws;

  /// Forward substitution L X = P E_S R restricted to the union of etree paths of S, R being
  /// |S| x r (identity when null). Returns X (rows: the path nodes, ascending), a view of a
  /// workspace valid until the next call.
  Eigen::Map<RowMat> forward(const std::vector<int>& S, const Eigen::MatrixXd* R = nullptr) const {
    extractL();
    std::vector<int> nodes;
    seen_ws.assign(n, 0);
    std::vector<char>& seen = seen_ws;
    for (int c : S) {
      if (c < 0 || c >= n) throw std::out_of_range("SparseCholesky: index out of range");
      for (int k = iperm[c]; k != -1 && !seen[k]; k = parent[k]) {
        seen[k] = 1;
        nodes.push_back(k);
      }
    }
    std::sort(nodes.begin(), nodes.end());
    local_ws.resize(n);
    std::vector<int>& local = local_ws;
    for (std::size_t a = 0; a < nodes.size(); ++a) local[nodes[a]] = static_cast<int>(a);
    const Eigen::Index cols = R ? R->cols() : static_cast<Eigen::Index>(S.size());
    const std::size_t size = nodes.size() * static_cast<std::size_t>(cols);
    if (x_ws.size() < size) x_ws.resize(size);
    std::fill(x_ws.begin(), x_ws.begin() + size, 0.0);
    Eigen::Map<RowMat> X(x_ws.data(), nodes.size(), cols);
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
  return impl_->Lp.back();
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
  detail::gramLower(X.data(), X.rows(), r, G.data());
  return G.selfadjointView<Eigen::Lower>();
}

Eigen::Map<const Eigen::MatrixXd> SparseCholesky::inverseGram(const std::vector<SparseColumn>& cols,
                                                              std::vector<int>* order) const {
  if (!impl_->ok) throw std::logic_error("SparseCholesky: no factorization");
  const Impl& m = *impl_;
  m.postorder();
  const int r = static_cast<int>(cols.size());
  order->resize(r);
  if (r == 0) return Eigen::Map<const Eigen::MatrixXd>(nullptr, 0, 0);
  // First node of each column (the first eliminated of its indices; the others are ancestors).
  std::vector<int>& start_node = m.start_ws;
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
  std::vector<int>&pos = m.pos_ws, &sorted_post = m.post_ws;
  pos.resize(r);
  sorted_post.resize(r);
  for (int p = 0; p < r; ++p) {
    pos[(*order)[p]] = p;
    sorted_post[p] = m.post[start_node[(*order)[p]]];
  }
  // The union of the etree paths, ascending, and each node's range of columns.
  std::vector<int>& nodes = m.nodes_ws;
  nodes.clear();
  m.mark_ws.resize(m.n, 0);
  for (int j = 0; j < r; ++j)
    for (int k = start_node[j]; k != -1 && !m.mark_ws[k]; k = m.parent[k]) {
      m.mark_ws[k] = 1;
      nodes.push_back(k);
    }
  for (const int k : nodes) m.mark_ws[k] = 0;  // clean for the next call
  std::sort(nodes.begin(), nodes.end());
  m.local_ws.resize(m.n);
  for (std::size_t a = 0; a < nodes.size(); ++a) m.local_ws[nodes[a]] = static_cast<int>(a);
  const std::size_t mm = nodes.size();
  std::vector<int>&lo = m.lo_ws, &hi = m.hi_ws;
  lo.resize(mm);
  hi.resize(mm);
  for (std::size_t a = 0; a < mm; ++a) {
    const int k = nodes[a];
    lo[a] = static_cast<int>(std::lower_bound(sorted_post.begin(), sorted_post.end(), m.first[k]) -
                             sorted_post.begin());
    hi[a] = static_cast<int>(std::upper_bound(sorted_post.begin(), sorted_post.end(), m.post[k]) -
                             sorted_post.begin());
  }
  // X = P R on the path rows (zero outside each row's range is never read), then L^-1.
  const std::size_t ld = static_cast<std::size_t>(r);
  if (m.x_ws.size() < mm * ld) m.x_ws.resize(mm * ld);
  double* X = m.x_ws.data();
  for (std::size_t a = 0; a < mm; ++a) std::fill(X + a * ld + lo[a], X + a * ld + hi[a], 0.0);
  for (int j = 0; j < r; ++j)
    for (int t = 0; t < cols[j].n; ++t)
      X[static_cast<std::size_t>(m.local_ws[m.iperm[cols[j].idx[t]]]) * ld + pos[j]] +=
          cols[j].val[t];
  detail::forwardSubstitutePath(X, ld, nodes.data(), mm, m.Lp.data(), m.Lnz.data(), m.Li.data(),
                                m.Lx.data(), m.local_ws.data(), lo.data(), hi.data());
  // Y^T Y (lower triangle): rows grouped by range, one blocked Gram product per group.
  std::vector<int>& by_range = m.range_ws;
  by_range.resize(mm);
  for (std::size_t a = 0; a < mm; ++a) by_range[a] = static_cast<int>(a);
  std::sort(by_range.begin(), by_range.end(),
            [&](int a, int b) { return lo[a] != lo[b] ? lo[a] < lo[b] : hi[a] < hi[b]; });
  if (m.g_ws.size() < ld * ld) m.g_ws.resize(ld * ld);
  std::fill(m.g_ws.begin(), m.g_ws.begin() + ld * ld, 0.0);
  for (std::size_t g = 0; g < mm;) {
    const int a0 = by_range[g];
    m.ptr_ws.clear();
    std::size_t e = g;
    for (; e < mm && lo[by_range[e]] == lo[a0] && hi[by_range[e]] == hi[a0]; ++e)
      m.ptr_ws.push_back(X + static_cast<std::size_t>(by_range[e]) * ld + lo[a0]);
    if (hi[a0] > lo[a0])
      detail::gramLowerRows(m.ptr_ws.data(), m.ptr_ws.size(),
                            static_cast<std::size_t>(hi[a0] - lo[a0]), m.g_ws.data(), ld,
                            static_cast<std::size_t>(lo[a0]));
    g = e;
  }
  return Eigen::Map<const Eigen::MatrixXd>(m.g_ws.data(), r, r);
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
