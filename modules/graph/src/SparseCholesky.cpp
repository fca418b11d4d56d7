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

  // Workspaces reused between calls: fresh multi-megabyte buffers per landmark cost more in
  // page faults than the arithmetic (not thread-safe; one backend per thread).
  mutable std::vector<char> seen_ws;
  mutable std::vector<int> local_ws;
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  mutable std::vector<double> x_ws;

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
