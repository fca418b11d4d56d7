// libFuzzer targets fuzz_convert_isam, fuzz_convert_g2o, fuzz_convert_utias and
// fuzz_convert_freiburg (this file compiled with BUDGET_SLAM_FUZZ_FORMAT = 0, 1, 2, 3): the
// converter over files made of the input (utias: Barcodes, Landmark_Groundtruth and robot 1's
// Odometry, Groundtruth and Measurement, split at separator lines, fuzz/FuzzFiles.h; freiburg:
// world.dat and sensor_data.dat), then, when it converts, the dataset saved as budget-convert
// saves it. Allowed outcomes: a dataset whose every reading and odometry step is within the
// input bounds (core/InputLimits.h) and whose sensor noise budget-slam accepts, or one Error of
// one printable line. A finding is anything else: a crash, a sanitizer report, another exception,
// an impossible value let through, an allocation above -malloc_limit_mb, a hang.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "FuzzFiles.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/Converters.h"
#include "budget_slam/dataset/DatasetFiles.h"

namespace {

using namespace budget_slam;

/// What the converter may never let through (issue 23, case 3).
void requireWithinBounds(const dataset::ConvertedDataset& d) {
  const auto std_ok = [](double s) { return s >= IniSection::kMinStd && s <= IniSection::kMaxStd; };
  if (!std_ok(d.noise.std_range) || !std_ok(d.noise.std_yaw)) __builtin_trap();
  for (const auto& s : d.steps) {
    if (s.odometry) {
      const auto& m = s.odometry->mean;
      if (!(std::abs(m.x) <= limits::kMaxStepTranslation &&
            std::abs(m.y) <= limits::kMaxStepTranslation && std::abs(m.phi) <= limits::kMaxAngle) ||
          !s.odometry->cov.allFinite() ||
          !(s.odometry->cov.cwiseAbs().maxCoeff() <= limits::kMaxVariance))
        __builtin_trap();
    }
    if (s.scan)
      for (const auto& r : s.scan->readings)
        if (!(r.range > 0 && r.range <= limits::kMaxRange &&
              std::abs(r.yaw) <= limits::kMaxAngle) ||
            r.id < 0 || r.id > limits::kMaxLandmarkId)
          __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = budget_slam::fuzz;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  static const char* kNames[] = {"isam", "g2o", "utias", "freiburg"};
  const int format = BUDGET_SLAM_FUZZ_FORMAT;
  const auto dir = fz::scratch(kNames[format]);
  try {
    dataset::ConvertedDataset d;
    if (format == 0 || format == 1) {
      const auto file = dir / (format == 0 ? "in.txt" : "in.g2o");
      fz::writeFile(file, std::string(bytes));
      d = format == 0 ? dataset::convertIsam(file.string()) : dataset::convertG2o(file.string());
    } else if (format == 2) {
      const char* names[] = {"Barcodes.dat", "Landmark_Groundtruth.dat", "Robot1_Odometry.dat",
                             "Robot1_Groundtruth.dat", "Robot1_Measurement.dat"};
      const auto files = fz::splitFiles(bytes, 5);
      for (int k = 0; k < 5; ++k) fz::writeFile(dir / names[k], files[k]);
      d = dataset::convertUtias(dir.string(), 1);
    } else {
      const auto files = fz::splitFiles(bytes, 2);
      fz::writeFile(dir / "world.dat", files[0]);
      fz::writeFile(dir / "sensor_data.dat", files[1]);
      d = dataset::convertFreiburg((dir / "world.dat").string(),
                                   (dir / "sensor_data.dat").string());
    }
    requireWithinBounds(d);
    dataset::saveDataset(d, (dir / "out.rawlog").string());
  } catch (const budget_slam::Error& e) {
    fz::requireOneLine(e.what());
  }
  return 0;
}
