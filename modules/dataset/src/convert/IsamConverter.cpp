#include <cmath>

#include "../TextTable.h"
#include "ConvertCommon.h"
#include "PoseChain.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/Converters.h"

namespace budget_slam::dataset {
namespace {
constexpr double kMinStd = IniSection::kMinStd;
}  // namespace

ConvertedDataset convertIsam(const std::string& path) {
  TextTable t(path);
  convert::PoseChain chain("ODOMETRY", "LANDMARK");
  double v1_sum = 0;
  while (t.next()) {
    const std::string& tag = t.word(0);
    if (tag == "ODOMETRY") {
      // ODOMETRY i j dx dy dtheta c11 c12 c13 c22 c23 c33 (covariance, as GTSAM reads it)
      t.expectFields(12, "ODOMETRY (i j dx dy dtheta + 6 covariance entries)");
      OdometryIncrement inc;
      inc.mean = {t.bounded(3, "dx", limits::kMaxStepTranslation),
                  t.bounded(4, "dy", limits::kMaxStepTranslation),
                  t.bounded(5, "dtheta", limits::kMaxAngle)};
      inc.cov = convert::upperTriangle3(t, 6, "covariance");
      convert::checkCovariance(t, inc.cov, "covariance", false);
      chain.addOdometry(t, t.integer(1, "pose id i"), t.integer(2, "pose id j"), inc);
    } else if (tag == "LANDMARK") {
      // LANDMARK i l x y v1 v2 v3: landmark l at (x, y) in the frame of pose i.
      t.expectFields(8, "LANDMARK (i l x y + 3 covariance entries)");
      const double x = t.bounded(3, "x", limits::kMaxRange),
                   y = t.bounded(4, "y", limits::kMaxRange);
      const double v1 = t.bounded(5, "v1", limits::kMaxVariance);
      t.bounded(6, "v2", limits::kMaxVariance), t.bounded(7, "v3", limits::kMaxVariance);
      // sqrt(v1) and sqrt(v1 / 10) must be standard deviations budget-slam accepts.
      if (!(v1 >= 10 * kMinStd * kMinStd))
        t.fail("variance v1 must be at least 1e-23, found '" + t.word(5) + "'");
      v1_sum += v1;
      const long long pose = t.integer(1, "pose id i"), landmark = t.landmarkId(2, "landmark id l");
      chain.addSighting(t, pose, landmark, std::hypot(x, y), std::atan2(y, x));
    } else {
      t.fail("unknown record '" + tag + "' (expected ODOMETRY or LANDMARK)");
    }
  }

  if (chain.sightingCount() == 0) throw InputError(path + ": no LANDMARK record (no sighting)");
  ConvertedDataset out;
  // GTSAM's example for this file (and Choudhary et al., who ran it in GTSAM): sigma_range =
  // sqrt(v1), sigma_bearing = sqrt(v1 / 10). One value for the whole file, as MRPT's filter takes.
  const double v1 = chain.sightingCount() ? v1_sum / chain.sightingCount() : 0;
  out.noise.std_range = std::sqrt(v1);
  out.noise.std_yaw = std::sqrt(v1 / 10);
  convert::limitsFromReadings(chain.readings(), out.noise);
  convert::checkSensorNoise(out.noise, path);
  out.steps = chain.build(t, out.noise);
  out.notes = {
      "Made by budget-convert --format isam from " + convert::baseName(path) + ".",
      "One step per ODOMETRY line (its mean and covariance as given); the LANDMARK lines of a",
      "pose go with the step that ends at that pose, as range = hypot(x, y), bearing = atan2(y, "
      "x).",
      "Times: step k at t = k + 1 s (the file has none). Landmark ids as in the file.",
      "Sensor noise as GTSAM uses this file: std_range = sqrt(v1), std_yaw = sqrt(v1 / 10) rad,",
      "v1 averaged over the LANDMARK lines. Limits below: the extremes of the readings.",
  };
  return out;
}

}  // namespace budget_slam::dataset
