#include "budget_slam/graph/GraphFactor.h"

namespace budget_slam::graph {

namespace {
GraphFactor make(GraphFactor::Kind kind, FactorId id, StepIndex pose, StepIndex from,
                 LandmarkId landmark) {
  GraphFactor g;
  g.kind = kind;
  g.id = id;
  g.pose = pose;
  g.from = from;
  g.landmark = landmark;
  return g;
}
}  // namespace

GraphFactor GraphFactor::posePrior(FactorId id, StepIndex pose, const PriorFactor& f) {
  GraphFactor g = make(Kind::PosePrior, id, pose, 0, 0);
  g.f = f;
  return g;
}

GraphFactor GraphFactor::odometry(FactorId id, StepIndex from, StepIndex to,
                                  const BetweenFactor& f) {
  GraphFactor g = make(Kind::Odometry, id, to, from, 0);
  g.f = f;
  return g;
}

GraphFactor GraphFactor::rangeBearing(FactorId id, StepIndex pose, LandmarkId landmark,
                                      const RangeBearingFactor& f) {
  GraphFactor g = make(Kind::RangeBearing, id, pose, 0, landmark);
  g.f = f;
  return g;
}

GraphFactor GraphFactor::landmarkPrior(FactorId id, LandmarkId landmark, const LandmarkPrior& f) {
  GraphFactor g = make(Kind::LandmarkPrior, id, 0, 0, landmark);
  g.f = f;
  return g;
}

int GraphFactor::variableCount() const {
  return kind == Kind::Odometry || kind == Kind::RangeBearing ? 2 : 1;
}

VariableKey GraphFactor::variable(int k) const {
  switch (kind) {
    case Kind::PosePrior:
      return VariableKey::pose(pose);
    case Kind::Odometry:
      return VariableKey::pose(k == 0 ? from : pose);
    case Kind::RangeBearing:
      return k == 0 ? VariableKey::pose(pose) : VariableKey::landmark(landmark);
    case Kind::LandmarkPrior:
      break;
  }
  return VariableKey::landmark(landmark);
}

LinearFactor linearize(const GraphFactor& f, const Eigen::Vector3d& x0, const Eigen::Vector3d& x1) {
  LinearFactor lf;
  switch (f.kind) {
    case GraphFactor::Kind::PosePrior: {
      const PriorFactor& p = std::get<PriorFactor>(f.f);
      Eigen::Matrix3d J;
      lf.rows = 3;
      lf.cols = 3;
      lf.r = p.sqrt_info * p.error(Pose2(x0), &J);
      lf.A.leftCols<3>() = p.sqrt_info * J;
      break;
    }
    case GraphFactor::Kind::Odometry: {
      const BetweenFactor& o = std::get<BetweenFactor>(f.f);
      Eigen::Matrix3d Ji, Jj;
      lf.rows = 3;
      lf.cols = 6;
      lf.r = o.sqrt_info * o.error(Pose2(x0), Pose2(x1), &Ji, &Jj);
      lf.A.leftCols<3>() = o.sqrt_info * Ji;
      lf.A.rightCols<3>() = o.sqrt_info * Jj;
      break;
    }
    case GraphFactor::Kind::RangeBearing: {
      const RangeBearingFactor& rb = std::get<RangeBearingFactor>(f.f);
      Eigen::Matrix<double, 2, 3> Jx;
      Eigen::Matrix2d Jl;
      lf.rows = 2;
      lf.cols = 5;
      lf.r.head<2>() = rb.sqrt_info * rb.error(Pose2(x0), x1.head<2>(), &Jx, &Jl);
      lf.A.topLeftCorner<2, 3>() = rb.sqrt_info * Jx;
      lf.A.block<2, 2>(0, 3) = rb.sqrt_info * Jl;
      break;
    }
    case GraphFactor::Kind::LandmarkPrior: {
      const LandmarkPrior& p = std::get<LandmarkPrior>(f.f);
      lf.rows = 2;
      lf.cols = 2;
      lf.r.head<2>() = p.sqrt_info * (x0.head<2>() - p.mean);
      lf.A.topLeftCorner<2, 2>() = p.sqrt_info;
      break;
    }
  }
  return lf;
}

}  // namespace budget_slam::graph
