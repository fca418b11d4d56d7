#include "budget_slam/graph/InformationGain.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <unordered_map>

#include "budget_slam/graph/Marginals.h"
#include "budget_slam/graph/Solver.h"

namespace budget_slam::graph {

void landmarkInformationOnPoses(const FactorGraph& graph, LandmarkId id, std::vector<StepIndex>* B,
                                Eigen::MatrixXd* W) {
  const LandmarkNode& l = graph.landmark(id);
  B->clear();
  std::unordered_map<StepIndex, int> slot;
  for (const Observation& o : l.obs)
    if (slot.emplace(o.pose, static_cast<int>(B->size())).second) B->push_back(o.pose);
  const int k = static_cast<int>(l.obs.size()) + (l.prior ? 1 : 0);
  const int nb = 3 * static_cast<int>(B->size());
  // Whitened Jacobian of L's k factors: columns [B poses | L]. A prior on L is a factor of L's
  // with no pose part.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * k, nb + 2);
  if (l.prior) A.block<2, 2>(2 * (k - 1), nb) = l.prior->sqrt_info;
  for (int f = 0; f < static_cast<int>(l.obs.size()); ++f) {
    const Observation& o = l.obs[f];
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::Matrix2d Jl;
    o.f.error(Pose2(graph.pose(o.pose).x), l.x, &Jx, &Jl);
    A.block<2, 3>(2 * f, 3 * slot[o.pose]) = o.f.sqrt_info * Jx;
    A.block<2, 2>(2 * f, nb) = o.f.sqrt_info * Jl;
  }
  // Eliminate L: Q^T [A_B A_L] = [R_BL... R_L; W 0]. The last 2k-2 rows of Q^T A_B are W.
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(A.rightCols<2>());
  const Eigen::MatrixXd QtAB = qr.householderQ().transpose() * A.leftCols(nb);
  *W = QtAB.bottomRows(std::max(0, 2 * k - 2));
}

namespace {

/// The whitened Jacobians of landmark L's k factors: the pose part as 2k sparse columns of
/// A_B^T (one per row of A_B, on the observing pose's three columns of H) and the landmark part
/// A_L (2k x 2).
void sightingJacobians(const FactorGraph& graph, LandmarkId l_id, std::vector<SparseColumn>* AB,
                       Eigen::MatrixXd* AL) {
  const LandmarkNode& l = graph.landmark(l_id);
  const int k = static_cast<int>(l.obs.size());
  const int rows = 2 * k + (l.prior ? 2 : 0);
  AB->assign(rows, SparseColumn{});
  AL->resize(rows, 2);
  if (l.prior) {  // a prior on L: rows with no pose part (a zero on L's own column)
    AL->bottomRows<2>() = l.prior->sqrt_info;
    const int c = graph.column(VariableKey::landmark(l_id));
    for (int row = 0; row < 2; ++row) {
      SparseColumn& col = (*AB)[2 * k + row];
      col.n = 1;
      col.idx[0] = c;
      col.val[0] = 0.0;
    }
  }
  for (int f = 0; f < k; ++f) {
    const Observation& o = l.obs[f];
    const PoseNode& p = graph.pose(o.pose);
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::Matrix2d Jl;
    o.f.error(Pose2(p.x), l.x, &Jx, &Jl);
    const Eigen::Matrix<double, 2, 3> Ax = o.f.sqrt_info * Jx;
    AL->block<2, 2>(2 * f, 0) = o.f.sqrt_info * Jl;
    const int c = graph.column(VariableKey::pose(o.pose));
    for (int row = 0; row < 2; ++row) {
      SparseColumn& col = (*AB)[2 * f + row];
      col.n = 3;
      for (int t = 0; t < 3; ++t) {
        col.idx[t] = c + t;
        col.val[t] = Ax(row, t);
      }
    }
  }
}

/// -1/2 log2 det(M) for a small SPD M given by its lower triangle, factorized in place; `spare`
/// keeps a copy for the fallback (LU on |det|) when round-off broke definiteness.
double minusHalfLog2Det(Eigen::Ref<Eigen::MatrixXd> M, std::vector<double>* spare) {
  const Eigen::Index n = M.rows();
  if (spare->size() < static_cast<std::size_t>(n * n)) spare->resize(n * n);
  Eigen::Map<Eigen::MatrixXd> copy(spare->data(), n, n);
  copy.triangularView<Eigen::Lower>() = M;
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(M);
  double logdet;
  if (llt.info() == Eigen::Success) {
    logdet = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  } else {
    const Eigen::MatrixXd full = copy.selfadjointView<Eigen::Lower>();
    logdet = std::log(std::abs(Eigen::PartialPivLU<Eigen::MatrixXd>(full).determinant()));
  }
  return -0.5 * logdet / std::log(2.0);
}

/// M <- H M H for the reflector H = I - tau v v^T, on the lower triangle of a symmetric M:
/// M - tau (v w^T + w v^T) + tau^2 (v^T M v) v v^T with w = M v (O(n^2)).
void reflectBothSides(Eigen::Ref<Eigen::MatrixXd> M, const Eigen::VectorXd& v, double tau) {
  if (tau == 0) return;
  const Eigen::VectorXd w = M.selfadjointView<Eigen::Lower>() * v;
  const double vMv = v.dot(w);
  // -tau (v w^T + w v^T) + tau^2 vMv v v^T = -tau (v u^T + u v^T), u = w - tau vMv / 2 v.
  const Eigen::VectorXd u = w - 0.5 * tau * vMv * v;
  M.selfadjointView<Eigen::Lower>().rankUpdate(v, u, -tau);
}

}  // namespace

std::vector<double> informationGain(const FactorGraph& graph, const SparseCholesky& chol,
                                    const std::vector<LandmarkId>& ids) {
  std::vector<double> out;
  out.reserve(ids.size());
  std::vector<SparseColumn> AB;
  Eigen::MatrixXd AL, ALs;
  std::vector<int> order;
  // Dense scratch of up to (2k)^2 doubles (a megabyte for the most seen landmark), kept per thread
  // between calls: fresh buffers of that size are page-faulted in on every call.
  thread_local std::vector<double> buf, spare;
  for (LandmarkId id : ids) {
    const LandmarkNode& l = graph.landmark(id);
    if (l.obs.size() + (l.prior ? 1 : 0) <= 1) {  // one factor: absorbed by L
      out.push_back(0.0);
      continue;
    }
    // M = A_B Sigma_BB A_B^T (2k x 2k) on the sightings' etree ranges, rows in the order the
    // factorization prefers; A_L's rows follow. With Q^T A_L = [R; 0] (Householder),
    // W = Q_2^T A_B and W Sigma_BB W^T = (Q^T M Q) without its first two rows and columns: two
    // reflections from each side, O(k^2).
    sightingJacobians(graph, id, &AB, &AL);
    const Eigen::Map<const Eigen::MatrixXd> G = chol.inverseGram(AB, &order);
    const Eigen::Index n = G.rows();
    ALs.resize(n, 2);
    for (Eigen::Index p = 0; p < n; ++p) ALs.row(p) = AL.row(order[p]);
    if (buf.size() < static_cast<std::size_t>(n * n)) buf.resize(n * n);
    Eigen::Map<Eigen::MatrixXd> M(buf.data(), n, n);
    M.triangularView<Eigen::Lower>() = G;
    for (Eigen::Index c = 0; c < 2; ++c) {  // Householder of column c of A_L, rows c..n-1
      Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
      double tau, beta;
      Eigen::VectorXd essential(n - c - 1);
      ALs.col(c).tail(n - c).makeHouseholder(essential, tau, beta);
      v(c) = 1.0;
      v.tail(n - c - 1) = essential;
      if (c == 0) {  // reflect A_L's second column too
        const double s = v.tail(n).dot(ALs.col(1));
        ALs.col(1) -= tau * s * v;
      }
      reflectBothSides(M, v, tau);
    }
    const Eigen::Index r = n - 2;
    // I - W Sigma_BB W^T: the covariance ratio of a conditioning, SPD in exact arithmetic.
    auto C = M.bottomRightCorner(r, r);
    C = -C;
    C.diagonal().array() += 1.0;
    out.push_back(minusHalfLog2Det(C, &spare));
  }
  return out;
}

std::vector<double> conditionalInformationGain(const FactorGraph& graph, const SparseCholesky& chol,
                                               const std::vector<LandmarkId>& ids) {
  std::vector<double> out;
  out.reserve(ids.size());
  std::vector<SparseColumn> cols;
  Eigen::MatrixXd AL;
  std::vector<int> order;
  std::vector<double> spare;
  for (LandmarkId id : ids) {
    const LandmarkNode& l = graph.landmark(id);
    const int k = static_cast<int>(l.obs.size()) + (l.prior ? 1 : 0);
    // Columns A_B^T and the two unit vectors of L: Gram [A S_BB A^T, A S_BL; ., S_LL].
    sightingJacobians(graph, id, &cols, &AL);
    const int c = graph.column(VariableKey::landmark(id));
    for (int t = 0; t < 2; ++t) {
      SparseColumn e;
      e.n = 1;
      e.idx[0] = c + t;
      e.val[0] = 1.0;
      cols.push_back(e);
    }
    const Eigen::Map<const Eigen::MatrixXd> Gs = chol.inverseGram(cols, &order);
    const int n = 2 * k + 2;
    Eigen::MatrixXd G(n, n);  // back to the columns' own order
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) G(order[a], order[b]) = a >= b ? Gs(a, b) : Gs(b, a);
    // A Sigma_{B|L} A^T = G11 - G12 G22^-1 G21 (conditioning on L).
    const Eigen::MatrixXd G12 = G.topRightCorner(2 * k, 2);
    const Eigen::Matrix2d G22 = G.bottomRightCorner<2, 2>();
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2 * k, 2 * k) - G.topLeftCorner(2 * k, 2 * k) +
                        G12 * G22.ldlt().solve(G12.transpose());
    out.push_back(minusHalfLog2Det(M, &spare));
  }
  return out;
}

double naiveInformationGain(const FactorGraph& graph, LandmarkId id) {
  // With L's factors: ln det(Sigma_r) = -ln det(H / H_LL) = -(ln det H - ln det H_LL).
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd g;
  graph.linearize(&H, &g);
  SparseCholesky full;
  if (!full.factorize(H)) throw std::runtime_error("graph: H is not positive definite");
  const int c = graph.column(VariableKey::landmark(id));
  // H_LL holds only L's factors; H stores its lower triangle.
  const double det_LL =
      H.coeff(c, c) * H.coeff(c + 1, c + 1) - H.coeff(c + 1, c) * H.coeff(c + 1, c);
  const double logdet_with = full.logDet() - std::log(det_LL);
  // Without: L and its factors removed, factorized from scratch.
  FactorGraph reduced = graph;
  reduced.removeLandmark(id);
  reduced.linearize(&H, &g);
  SparseCholesky without;
  if (!without.factorize(H)) throw std::runtime_error("graph: H is not positive definite");
  return 0.5 * (logdet_with - without.logDet()) / std::log(2.0);
}

}  // namespace budget_slam::graph
