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
  const int k = static_cast<int>(l.obs.size());
  const int nb = 3 * static_cast<int>(B->size());
  // Whitened Jacobian of L's k factors: columns [B poses | L].
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * k, nb + 2);
  for (int f = 0; f < k; ++f) {
    const Observation& o = l.obs[f];
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::Matrix2d Jl;
    o.f.error(graph.pose(o.pose).x, l.x, &Jx, &Jl);
    A.block<2, 3>(2 * f, 3 * slot[o.pose]) = o.f.sqrt_info * Jx;
    A.block<2, 2>(2 * f, nb) = o.f.sqrt_info * Jl;
  }
  // Eliminate L: Q^T [A_B A_L] = [R_BL... R_L; W 0]. The last 2k-2 rows of Q^T A_B are W.
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(A.rightCols<2>());
  const Eigen::MatrixXd QtAB = qr.householderQ().transpose() * A.leftCols(nb);
  *W = QtAB.bottomRows(std::max(0, 2 * k - 2));
}

std::vector<double> informationGain(const FactorGraph& graph, const SparseCholesky& chol,
                                    const std::vector<LandmarkId>& ids) {
  std::vector<double> out;
  out.reserve(ids.size());
  std::vector<StepIndex> B;
  Eigen::MatrixXd W;
  for (LandmarkId id : ids) {
    if (graph.landmark(id).obs.size() <= 1) {  // seen once: L's factor is absorbed by L
      out.push_back(0.0);
      continue;
    }
    landmarkInformationOnPoses(graph, id, &B, &W);
    std::vector<VariableKey> vars;
    vars.reserve(B.size());
    for (StepIndex s : B) vars.push_back(VariableKey::pose(s));
    const Eigen::MatrixXd WSW = chol.inverseQuadraticForm(columnsOf(graph, vars), W);
    const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(W.rows(), W.rows()) - WSW;
    // M = I - W Sigma W^T is the covariance ratio of a conditioning, SPD in exact arithmetic.
    Eigen::LLT<Eigen::MatrixXd> llt(M);
    double logdet;
    if (llt.info() == Eigen::Success) {
      logdet = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
    } else {
      logdet = std::log(std::abs(Eigen::PartialPivLU<Eigen::MatrixXd>(M).determinant()));
    }
    out.push_back(-0.5 * logdet / std::log(2.0));
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
