#pragma once
#include <Eigen/LU>
#include <cmath>
#include <random>

#include "budget_slam/gaussian/GaussianStateBackend.h"

namespace budget_slam::testing {

/// A random SPD covariance of size n: A A^T + 0.1 I with Gaussian A (dense correlations, as an
/// EKF that has run for a while).
inline Eigen::MatrixXd randomSpd(int n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = g(rng);
  return A * A.transpose() / n + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

/// N landmarks with ids 10, 11, ..., last seen at step 0, over a random SPD state.
inline gaussian::GaussianStateBackend randomState(int n_landmarks, std::mt19937& rng,
                                                  StepIndex step = 100) {
  std::vector<LandmarkView> lms(n_landmarks);
  std::uniform_real_distribution<double> u(0, 50);
  for (int i = 0; i < n_landmarks; ++i) {
    lms[i].id = 10 + i;
    lms[i].n_obs = 3;
    lms[i].obs_mean = Eigen::Vector2d(u(rng), u(rng));
  }
  return gaussian::GaussianStateBackend(lms, randomSpd(3 + 2 * n_landmarks, rng), step);
}

/// Independent brute force of I(L; rest) [bits]: 1/2 log2(det(P_LL) det((P^-1)_LL)) with a full
/// LU inverse of P; `r` is the first row of L.
inline double bruteForceGain(const Eigen::MatrixXd& P, Eigen::Index r) {
  const Eigen::MatrixXd Lambda = P.fullPivLu().inverse();
  return 0.5 *
         std::log2(P.block(r, r, 2, 2).determinant() * Lambda.block(r, r, 2, 2).determinant());
}

/// Brute-force gains of every landmark of a state laid out robot, then landmarks.
inline std::vector<double> bruteForceGains(const Eigen::MatrixXd& P) {
  std::vector<double> out;
  const Eigen::MatrixXd Lambda = P.fullPivLu().inverse();
  for (Eigen::Index r = 3; r < P.rows(); r += 2)
    out.push_back(0.5 * std::log2(P.block(r, r, 2, 2).determinant() *
                                  Lambda.block(r, r, 2, 2).determinant()));
  return out;
}

/// P without rows and columns [r, r+2).
inline Eigen::MatrixXd eraseBlock(const Eigen::MatrixXd& P, Eigen::Index r) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (i != r && i != r + 1) keep.push_back(i);
  Eigen::MatrixXd out(keep.size(), keep.size());
  for (std::size_t i = 0; i < keep.size(); ++i)
    for (std::size_t j = 0; j < keep.size(); ++j) out(i, j) = P(keep[i], keep[j]);
  return out;
}

}  // namespace budget_slam::testing

namespace budget_slam::testing {

/// Choudhary et al. Alg. 3 by brute force on a Gaussian state (robot then landmarks `ids`):
/// full inverses at every greedy step, rho of Eq. 4 with d normalised by the largest d of the
/// sequence, stop at the first increase. Landmarks with `is_candidate` false never go.
/// Returns the dropped ids and their gains, in order.
inline std::vector<std::pair<LandmarkId, double>> bruteForceObjective(
    Eigen::MatrixXd P, std::vector<LandmarkId> ids, const std::vector<bool>& is_candidate_in,
    double lambda) {
  std::vector<bool> is_candidate = is_candidate_in;
  const double N = static_cast<double>(ids.size());
  std::vector<std::pair<LandmarkId, double>> seq;
  for (;;) {
    const auto g = bruteForceGains(P);
    std::size_t best = ids.size();
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (is_candidate[i] &&
          (best == ids.size() || g[i] < g[best] || (g[i] == g[best] && ids[i] < ids[best])))
        best = i;
    if (best == ids.size()) break;
    seq.emplace_back(ids[best], g[best]);
    P = eraseBlock(P, 3 + 2 * static_cast<Eigen::Index>(best));
    ids.erase(ids.begin() + static_cast<long>(best));
    is_candidate.erase(is_candidate.begin() + static_cast<long>(best));
  }
  double D = 0;
  for (const auto& s : seq) D = std::max(D, s.second);
  double prev = lambda;
  std::size_t k = 0;
  for (; k < seq.size(); ++k) {
    const double d = D > 0 ? std::max(0.0, seq[k].second) / D : 0.0;
    const double rho = (1 - lambda) * d + lambda * (N - static_cast<double>(k + 1)) / N;
    if (rho > prev) break;
    prev = rho;
  }
  seq.resize(k);
  return seq;
}

}  // namespace budget_slam::testing
