#include "budget_slam/wakeup/WindowFit.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <unordered_map>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/RangeBearingModel.h"

namespace budget_slam::wakeup {
namespace {

/// The normal equations H dx = g of one Gauss-Newton step, split into the rest r (every pose but
/// the latest, then the landmarks) and the latest pose l: H_rr sparse (block tridiagonal in the
/// poses, plus the landmark blocks), H_rl and H_ll dense.
struct Normal {
  std::size_t rest = 0;  ///< size of r
  std::vector<Eigen::Triplet<double>> rr;
  Eigen::MatrixXd rl;
  Eigen::Matrix3d ll = Eigen::Matrix3d::Zero();
  Eigen::VectorXd g_r;
  Eigen::Vector3d g_l = Eigen::Vector3d::Zero();

  explicit Normal(std::size_t r)
      : rest(r), rl(Eigen::MatrixXd::Zero(r, 3)), g_r(Eigen::VectorXd::Zero(r)) {}

  /// Adds J^T W J and J^T W e for a factor whose Jacobian has the blocks `Ja` at variable offset
  /// `a` and `Jb` at `b` (b < 0: one block only).
  template <int E, int A, int B>
  void add(const Eigen::Matrix<double, E, A>& Ja, long a, const Eigen::Matrix<double, E, B>& Jb,
           long b, const Eigen::Matrix<double, E, E>& W, const Eigen::Matrix<double, E, 1>& e) {
    block(Ja.transpose() * W * Ja, a, a);
    gradient(Ja.transpose() * W * e, a);
    if (b < 0) return;
    block(Jb.transpose() * W * Jb, b, b);
    gradient(Jb.transpose() * W * e, b);
    const Eigen::MatrixXd cross = Ja.transpose() * W * Jb;
    block(cross, a, b);
    block(cross.transpose(), b, a);
  }

 private:
  void block(const Eigen::MatrixXd& m, long i, long j) {
    const auto r = static_cast<long>(rest);
    for (long u = 0; u < m.rows(); ++u)
      for (long v = 0; v < m.cols(); ++v) {
        const long row = i + u, col = j + v;
        if (row < r && col < r)
          rr.emplace_back(row, col, m(u, v));
        else if (row < r)
          rl(row, col - r) += m(u, v);
        else if (col >= r)
          ll(row - r, col - r) += m(u, v);
        // (l, r): the transpose of rl, not stored.
      }
  }
  void gradient(const Eigen::VectorXd& v, long i) {
    for (long u = 0; u < v.size(); ++u) {
      if (i + u < static_cast<long>(rest))
        g_r(i + u) += v(u);
      else
        g_l(i + u - static_cast<long>(rest)) += v(u);
    }
  }
};

/// Step halvings tried before a Gauss-Newton step is taken as no descent.
constexpr int kMaxHalvings = 20;
/// Converged when a step lowers the cost by less than this share of it.
constexpr double kRelativeDecrease = 1e-12;

Eigen::Matrix3d floored(const Eigen::Matrix3d& c) {
  return c + kCovarianceFloor * Eigen::Matrix3d::Identity();
}
Eigen::Matrix2d floored(const Eigen::Matrix2d& c) {
  return c + kCovarianceFloor * Eigen::Matrix2d::Identity();
}

}  // namespace

Refinement fitWindow(const Pose2& start, const std::vector<WindowStep>& steps,
                     const std::vector<LocalReading>& readings,
                     const std::vector<LandmarkView>& map, const std::vector<Pairing>& pairs,
                     const ReadingNoise& noise, WindowLandmarks landmarks, int max_iterations) {
  Refinement out;
  out.pose = start;
  out.chi2.assign(pairs.size(), 0);
  if (steps.empty() || pairs.empty()) return out;
  const std::size_t n = steps.size();
  std::unordered_map<StepIndex, std::size_t> slot;
  for (std::size_t j = 0; j < n; ++j) slot[steps[j].index] = j;
  // Variables: X_0 .. X_{n-2} (3 each), the named landmarks (2 each), then X_{n-1}.
  std::unordered_map<std::size_t, std::size_t> landmark_slot;  // map index -> 0, 1, ...
  std::vector<std::size_t> named;
  for (const auto& p : pairs)
    if (landmark_slot.emplace(p.landmark, named.size()).second) named.push_back(p.landmark);
  const std::size_t free_landmarks = landmarks == WindowLandmarks::Priors ? named.size() : 0;
  const std::size_t rest = 3 * (n - 1) + 2 * free_landmarks;
  const auto poseAt = [&](std::size_t j) -> long {
    return static_cast<long>(j + 1 == n ? rest : 3 * j);
  };
  const auto landmarkAt = [&](std::size_t q) -> long {
    return static_cast<long>(3 * (n - 1) + 2 * q);
  };

  std::vector<Pose2> X(n);
  for (std::size_t j = 0; j < n; ++j) X[j] = compose(start, steps[j].pose);
  std::vector<Eigen::Vector2d> L;
  for (const auto m : named) L.push_back(map[m].mean);

  const Eigen::Matrix2d Rn =
      Eigen::Vector2d(noise.std_range * noise.std_range, noise.std_bearing * noise.std_bearing)
          .asDiagonal();
  const Eigen::Matrix2d Rinv = Rn.inverse();
  std::vector<Eigen::Matrix3d> Qinv(n);
  for (std::size_t j = 1; j < n; ++j) Qinv[j] = floored(steps[j].odometry_cov).inverse();
  std::vector<Eigen::Matrix2d> Pinv;
  for (const auto m : named) Pinv.push_back(floored(map[m].cov).inverse());

  // The weighted sum of squared residuals (twice the negative log-likelihood, up to a constant).
  const auto cost = [&](const std::vector<Pose2>& Xc, const std::vector<Eigen::Vector2d>& Lc) {
    double c = 0;
    for (std::size_t j = 1; j < n; ++j) {
      Eigen::Vector3d e = steps[j].odometry.vector() - between(Xc[j - 1], Xc[j]).vector();
      e.z() = wrapAngle(e.z());
      c += e.dot(Qinv[j] * e);
    }
    for (const auto& p : pairs) {
      const std::size_t j = slot.at(readings[p.reading].step);
      Eigen::Vector2d nu =
          readings[p.reading].z -
          predictRangeBearing(Xc[j], steps[j].on_robot, Lc[landmark_slot.at(p.landmark)]).z;
      nu.y() = wrapAngle(nu.y());
      c += nu.dot(Rinv * nu);
    }
    for (std::size_t q = 0; q < free_landmarks; ++q) {
      const Eigen::Vector2d e = map[named[q]].mean - Lc[q];
      c += e.dot(Pinv[q] * e);
    }
    return c;
  };
  double current = cost(X, L);

  for (int it = 0; it <= max_iterations; ++it) {
    Cancellation::check();  // a stop ends the wake-up within a second (WakeUpRun.cpp)
    Normal N(rest);
    for (std::size_t j = 1; j < n; ++j) {
      Eigen::Matrix3d Ja, Jb;
      const Pose2 pred = between(X[j - 1], X[j], &Ja, &Jb);
      Eigen::Vector3d e = steps[j].odometry.vector() - pred.vector();
      e.z() = wrapAngle(e.z());
      N.add<3, 3, 3>(Ja, poseAt(j - 1), Jb, poseAt(j), Qinv[j], e);
    }
    for (const auto& p : pairs) {
      const LocalReading& r = readings[p.reading];
      const std::size_t j = slot.at(r.step), q = landmark_slot.at(p.landmark);
      const auto pr = predictRangeBearing(X[j], steps[j].on_robot, L[q]);
      Eigen::Vector2d nu = r.z - pr.z;
      nu.y() = wrapAngle(nu.y());
      const Eigen::Matrix<double, 2, 3> Jx = pr.H_robot;
      const Eigen::Matrix2d Jl = pr.H_landmark;
      N.add<2, 3, 2>(Jx, poseAt(j), Jl, free_landmarks > 0 ? landmarkAt(q) : -1, Rinv, nu);
    }
    for (std::size_t q = 0; q < free_landmarks; ++q) {
      const Eigen::Vector2d e = map[named[q]].mean - L[q];
      const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
      N.add<2, 2, 2>(I, landmarkAt(q), I, -1, Pinv[q], e);
    }
    // Eliminate the rest: S = H_ll - H_lr H_rr^-1 H_rl, the latest pose's marginal information.
    Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(static_cast<long>(rest), 3);  // H_rr^-1 H_rl
    Eigen::VectorXd y = Eigen::VectorXd::Zero(static_cast<long>(rest));     // H_rr^-1 g_r
    if (rest > 0) {
      Eigen::SparseMatrix<double> Hrr(static_cast<long>(rest), static_cast<long>(rest));
      Hrr.setFromTriplets(N.rr.begin(), N.rr.end());
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(Hrr);
      if (solver.info() != Eigen::Success) return out;
      Y = solver.solve(N.rl);
      y = solver.solve(N.g_r);
    }
    const Eigen::Matrix3d S = N.ll - N.rl.transpose() * Y;
    out.information = 0.5 * (S + S.transpose());
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(out.information);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return out;
    out.cov = ldlt.solve(Eigen::Matrix3d::Identity());
    if (it == max_iterations || out.converged) break;
    const Eigen::Vector3d dl = ldlt.solve(N.g_l - N.rl.transpose() * y);
    const Eigen::VectorXd dr = y - Y * dl;
    // Gauss-Newton step, halved while it raises the cost (a reading far off its landmark makes
    // the problem a large-residual one, where the full step can overshoot).
    double scale = 1, largest = 0, next = current;
    std::vector<Pose2> Xn;
    std::vector<Eigen::Vector2d> Ln;
    for (int halvings = 0; halvings <= kMaxHalvings; ++halvings, scale *= 0.5) {
      Xn = X;
      Ln = L;
      largest = scale * dl.cwiseAbs().maxCoeff();
      for (std::size_t j = 0; j < n; ++j) {
        const Eigen::Vector3d d =
            scale * (j + 1 == n ? dl : Eigen::Vector3d(dr.segment<3>(poseAt(j))));
        Xn[j] = Pose2(Xn[j].vector() + d);
        Xn[j].phi = wrapAngle(Xn[j].phi);
        largest = std::max(largest, d.cwiseAbs().maxCoeff());
      }
      for (std::size_t q = 0; q < free_landmarks; ++q) {
        const Eigen::Vector2d d = scale * dr.segment<2>(landmarkAt(q));
        Ln[q] += d;
        largest = std::max(largest, d.cwiseAbs().maxCoeff());
      }
      next = cost(Xn, Ln);
      if (next <= current) break;
    }
    if (next > current) {
      // No step lowers the cost: at the minimum, up to rounding.
      out.converged = true;
      continue;
    }
    X = std::move(Xn);
    L = std::move(Ln);
    out.pose = X[n - 1];
    // One more pass after convergence evaluates the information at the solution.
    if (largest < 1e-9 || current - next <= kRelativeDecrease * current) out.converged = true;
    current = next;
  }
  // Each reading against the map's landmark, under its step's fitted pose.
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const LocalReading& r = readings[pairs[k].reading];
    const LandmarkView& l = map[pairs[k].landmark];
    const std::size_t j = slot.at(r.step);
    const auto pr = predictRangeBearing(X[j], steps[j].on_robot, l.mean);
    Eigen::Vector2d nu = r.z - pr.z;
    nu.y() = wrapAngle(nu.y());
    const Eigen::Matrix2d Si = Rn + pr.H_landmark * l.cov * pr.H_landmark.transpose();
    out.chi2[k] = nu.dot(Si.ldlt().solve(nu));
  }
  return out;
}

}  // namespace budget_slam::wakeup
