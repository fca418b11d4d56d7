#include "budget_slam/graph/Factors.h"

#include "budget_slam/core/RangeBearingModel.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace budget_slam::graph {

namespace {
template <int N>
Eigen::Matrix<double, N, N> sqrtInfo(const Eigen::Matrix<double, N, N>& cov) {
  using M = Eigen::Matrix<double, N, N>;
  if (!cov.allFinite() || !cov.isApprox(cov.transpose(), 1e-9))
    throw std::invalid_argument("covariance is not finite and symmetric");
  const M sym = 0.5 * (cov + cov.transpose());
  // cov = L L^T  =>  cov^-1 = L^-T L^-1, so S = L^-1 satisfies S^T S = cov^-1. S is lower
  // triangular; any square root works for whitening, this one needs no explicit inverse of cov.
  Eigen::LLT<M> llt(sym);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("covariance is not positive definite");
  M S = M::Identity();
  llt.matrixL().solveInPlace(S);
  return S;
}
}  // namespace

Eigen::Matrix3d sqrtInformation(const Eigen::Matrix3d& cov) { return sqrtInfo<3>(cov); }
Eigen::Matrix2d sqrtInformation(const Eigen::Matrix2d& cov) { return sqrtInfo<2>(cov); }

PriorFactor PriorFactor::make(const Pose2& mean, const Eigen::Matrix3d& cov) {
  PriorFactor f;
  f.mean = mean;
  f.cov = cov;
  f.sqrt_info = sqrtInformation(cov);
  return f;
}

Eigen::Vector3d PriorFactor::error(const Pose2& x, Eigen::Matrix3d* J) const {
  if (J) J->setIdentity();
  return Eigen::Vector3d(x.x - mean.x, x.y - mean.y, wrapAngle(x.phi - mean.phi));
}

BetweenFactor BetweenFactor::make(const Pose2& z, const Eigen::Matrix3d& cov) {
  BetweenFactor f;
  f.z = z;
  f.cov = cov;
  f.sqrt_info = sqrtInformation(cov);
  return f;
}

Eigen::Vector3d BetweenFactor::error(const Pose2& xi, const Pose2& xj, Eigen::Matrix3d* Ji,
                                     Eigen::Matrix3d* Jj) const {
  const Pose2 h = between(xi, xj, Ji, Jj);
  return Eigen::Vector3d(h.x - z.x, h.y - z.y, wrapAngle(h.phi - z.phi));
}

RangeBearingFactor RangeBearingFactor::make(double range, double bearing, const Pose2& sensor,
                                            const Eigen::Matrix2d& cov) {
  RangeBearingFactor f;
  f.range = range;
  f.bearing = bearing;
  f.sensor = sensor;
  f.cov = cov;
  f.sqrt_info = sqrtInformation(cov);
  return f;
}

Eigen::Vector2d RangeBearingFactor::predict(const Pose2& x, const Eigen::Vector2d& l,
                                            Eigen::Matrix<double, 2, 3>* Jx,
                                            Eigen::Matrix2d* Jl) const {
  const RangeBearingPrediction p = predictRangeBearing(x, sensor, l);
  if (Jx) *Jx = p.H_robot;
  if (Jl) *Jl = p.H_landmark;
  return p.z;
}

Eigen::Vector2d RangeBearingFactor::error(const Pose2& x, const Eigen::Vector2d& l,
                                          Eigen::Matrix<double, 2, 3>* Jx,
                                          Eigen::Matrix2d* Jl) const {
  const Eigen::Vector2d h = predict(x, l, Jx, Jl);
  return Eigen::Vector2d(h.x() - range, wrapAngle(h.y() - bearing));
}

Eigen::Vector2d RangeBearingFactor::landmarkFrom(const Pose2& x) const {
  return readingPoint(range, bearing, compose(x, sensor));
}

LandmarkPrior LandmarkPrior::make(const Eigen::Vector2d& mean, const Eigen::Matrix2d& cov) {
  LandmarkPrior p;
  p.mean = mean;
  // sqrt_info = L^-1 for cov = L L^T: sqrt_info^T sqrt_info = cov^-1.
  const Eigen::LLT<Eigen::Matrix2d> llt(0.5 * (cov + cov.transpose()));
  if (llt.info() != Eigen::Success || !cov.allFinite())
    throw std::invalid_argument("graph: landmark prior covariance is not positive definite");
  p.sqrt_info = llt.matrixL().solve(Eigen::Matrix2d::Identity());
  return p;
}

BetweenFactor composeBetween(const BetweenFactor& a, const BetweenFactor& b) {
  Eigen::Matrix3d Ja, Jb;
  const Pose2 z = compose(a.z, b.z, &Ja, &Jb);
  Eigen::Matrix3d cov = Ja * a.cov * Ja.transpose() + Jb * b.cov * Jb.transpose();
  cov = 0.5 * (cov + cov.transpose());
  return BetweenFactor::make(z, cov);
}

}  // namespace budget_slam::graph
