#pragma once
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// Information gain of landmark L in bits (Choudhary et al. Eq. 6, Alg. 2; docs/GRAPH.md
/// "Information gain"):
///   IG(L) = 1/2 log2( |Sigma_r without L's factors| / |Sigma_r with them| ),  r = all but L.
///
/// Fast form, from one factorization of the full H shared by every landmark. Let B be the poses
/// that observe L. L's factors, with L eliminated, put on B the information
///   U = H_BB - H_BL H_LL^-1 H_LB   (over L's factors only).
/// The information of r with L's factors is that of r without them plus U, and its inverse is
/// the full graph's marginal Sigma_rr, so by the determinant lemma
///   IG(L) = -1/2 log2 det(I - Sigma_BB U),  Sigma_BB the joint marginal of B in the full graph.
/// U is formed in square-root form: QR-eliminating L from the whitened Jacobian [A_B A_L] of its
/// k factors leaves 2k-2 rows W with U = W^T W, and det(I - Sigma_BB U) = det(I - W Sigma_BB W^T),
/// a small SPD determinant. W Sigma_BB W^T is A_B Sigma_BB A_B^T (one forward substitution with
/// the 2k sparse rows of A_B as right-hand sides, SparseCholesky::inverseGram) reflected from both
/// sides by the two Householder reflectors that eliminate L, minus their two rows and columns.
/// A landmark seen once has k = 1, no row left, and IG = 0 exactly.
///
/// `chol` must hold the factorization of the graph's H at its current estimate
/// (factorizeAtEstimate). Throws std::out_of_range for an unknown id.
std::vector<double> informationGain(const FactorGraph& graph, const SparseCholesky& chol,
                                    const std::vector<LandmarkId>& ids);

/// Choudhary et al. Alg. 2 as printed: the "with" term is |Sigma_{r|L}|, r conditioned on L
/// (line 2: eliminate r with L in the graph), not marginalized over it:
///   IG_c(L) = 1/2 log2( |Sigma_r without L's factors| / |Sigma_{r|L} with them| )
///           = -1/2 log2 det(I - A_B Sigma_{B|L} A_B^T),
/// A_B the whitened pose Jacobians of L's k factors (2k rows), Sigma_{B|L} = Sigma_BB -
/// Sigma_BL Sigma_LL^-1 Sigma_LB from the full graph (one forward substitution with 2k + 2
/// right-hand sides). A landmark seen once has IG_c > 0: its factor fixes the pose to a known L.
std::vector<double> conditionalInformationGain(const FactorGraph& graph, const SparseCholesky& chol,
                                               const std::vector<LandmarkId>& ids);

/// The sqrt-information rows W of U for landmark `id` and the poses B they act on (exposed for
/// tests: U = W^T W equals H_BB - H_BL H_LL^-1 H_LB built from the dense information).
void landmarkInformationOnPoses(const FactorGraph& graph, LandmarkId id, std::vector<StepIndex>* B,
                                Eigen::MatrixXd* W);

/// Naive reference, Alg. 1-2 literally: for each landmark, relinearize and factorize twice from
/// scratch (symbolic analysis included):
///   ln|Sigma_r with| = -(ln det H_full - ln det H_LL)   (L marginalized: Schur complement),
///   ln|Sigma_r without| = -ln det H_without             (L and its factors removed),
/// log-determinants from the Cholesky diagonals (Alg. 1, Eq. 7). Cost: two sparse factorizations
/// per landmark. Kept for tests and benchmarks.
double naiveInformationGain(const FactorGraph& graph, LandmarkId id);

}  // namespace budget_slam::graph
