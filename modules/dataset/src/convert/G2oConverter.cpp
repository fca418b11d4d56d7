#include <Eigen/LU>
#include <cmath>
#include <map>

#include "../TextTable.h"
#include "ConvertCommon.h"
#include "PoseChain.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/Converters.h"

namespace budget_slam::dataset {

ConvertedDataset convertG2o(const std::string& path) {
  TextTable t(path);
  convert::PoseChain chain("EDGE_SE2", "EDGE_SE2_XY");
  std::map<long long, std::size_t> se2, xy;                          // declared vertices -> line
  std::vector<std::pair<long long, std::size_t>> need_se2, need_xy;  // (id, line) referenced
  double var_range_sum = 0, var_yaw_sum = 0;
  std::size_t n_xy = 0;
  auto declare = [&](std::map<long long, std::size_t>& into, long long id) {
    if (se2.count(id) || xy.count(id))
      t.fail("vertex " + std::to_string(id) + " is declared twice (first on line " +
             std::to_string(se2.count(id) ? se2[id] : xy[id]) + ")");
    into[id] = t.line();
  };
  while (t.next()) {
    const std::string& tag = t.word(0);
    if (tag == "VERTEX_SE2") {
      // Initial guesses only: the rawlog carries the measurements.
      t.expectFields(5, "VERTEX_SE2 (id x y theta)");
      t.bounded(2, "x", limits::kMaxCoordinate), t.bounded(3, "y", limits::kMaxCoordinate);
      t.bounded(4, "theta", limits::kMaxAngle);
      declare(se2, t.integer(1, "vertex id"));
    } else if (tag == "VERTEX_XY") {
      t.expectFields(4, "VERTEX_XY (id x y)");
      t.bounded(2, "x", limits::kMaxCoordinate), t.bounded(3, "y", limits::kMaxCoordinate);
      declare(xy, t.integer(1, "vertex id"));
    } else if (tag == "EDGE_SE2") {
      // EDGE_SE2 i j dx dy dtheta + upper triangle of the 3x3 information matrix.
      t.expectFields(12, "EDGE_SE2 (i j dx dy dtheta + 6 information entries)");
      OdometryIncrement inc;
      inc.mean = {t.bounded(3, "dx", limits::kMaxStepTranslation),
                  t.bounded(4, "dy", limits::kMaxStepTranslation),
                  t.bounded(5, "dtheta", limits::kMaxAngle)};
      const Eigen::Matrix3d info = convert::upperTriangle3(t, 6, "information");
      convert::checkCovariance(t, info, "information matrix", true);
      inc.cov = convert::covarianceOfInformation(t, info);
      const long long i = t.integer(1, "vertex id i"), j = t.integer(2, "vertex id j");
      need_se2.emplace_back(i, t.line());
      need_se2.emplace_back(j, t.line());
      chain.addOdometry(t, i, j, inc);
    } else if (tag == "EDGE_SE2_XY") {
      // EDGE_SE2_XY i l x y + upper triangle of the 2x2 information matrix (robot frame).
      t.expectFields(8, "EDGE_SE2_XY (i l x y + 3 information entries)");
      const double x = t.bounded(3, "x", limits::kMaxRange),
                   y = t.bounded(4, "y", limits::kMaxRange);
      const Eigen::Matrix2d info = convert::upperTriangle2(t, 5, "information");
      convert::checkCovariance(t, info, "information matrix", true);
      const Eigen::Matrix2d cov = convert::covarianceOfInformation(t, info);
      const long long i = t.integer(1, "vertex id i"), l = t.landmarkId(2, "vertex id l");
      need_se2.emplace_back(i, t.line());
      need_xy.emplace_back(l, t.line());
      const double r = std::hypot(x, y);
      chain.addSighting(t, i, l, r, std::atan2(y, x));
      // First-order propagation of the Cartesian covariance to (range, bearing).
      Eigen::Matrix2d J;
      J << x / r, y / r, -y / (r * r), x / (r * r);
      const Eigen::Matrix2d c = J * cov * J.transpose();
      if (!c.allFinite() || !(c.cwiseAbs().maxCoeff() <= limits::kMaxVariance))
        t.fail("the sighting's covariance in range and bearing is beyond 1e24");
      var_range_sum += c(0, 0);
      var_yaw_sum += c(1, 1);
      ++n_xy;
    } else if (tag == "FIX") {
      // The first pose is the origin of the rawlog anyway.
    } else {
      t.fail("unknown record '" + tag +
             "' (expected VERTEX_SE2, VERTEX_XY, EDGE_SE2, EDGE_SE2_XY or FIX)");
    }
  }
  for (const auto& [id, line] : need_se2)
    if (!se2.count(id))
      throw InputError(t.where(line) + ": vertex " + std::to_string(id) +
                       " is not declared by a VERTEX_SE2 line");
  for (const auto& [id, line] : need_xy)
    if (!xy.count(id))
      throw InputError(t.where(line) + ": vertex " + std::to_string(id) +
                       " is not declared by a VERTEX_XY line");

  if (n_xy == 0) throw InputError(path + ": no EDGE_SE2_XY record (no landmark sighting)");
  ConvertedDataset out;
  out.noise.std_range = n_xy ? std::sqrt(var_range_sum / n_xy) : 0;
  out.noise.std_yaw = n_xy ? std::sqrt(var_yaw_sum / n_xy) : 0;
  convert::limitsFromReadings(chain.readings(), out.noise);
  convert::checkSensorNoise(out.noise, path);
  out.steps = chain.build(t, out.noise);
  out.notes = {
      "Made by budget-convert --format g2o from " + convert::baseName(path) + ".",
      "One step per EDGE_SE2 (mean; covariance = inverse of its information matrix); the",
      "EDGE_SE2_XY of a pose go with the step that ends at it, as range and bearing. Vertex",
      "values (initial guesses) are not used. Times: step k at t = k + 1 s. Ids as in the file.",
      "Sensor noise: each EDGE_SE2_XY covariance propagated to range and bearing (first order),",
      "RMS over the file. Limits below: the extremes of the readings.",
  };
  return out;
}

}  // namespace budget_slam::dataset
