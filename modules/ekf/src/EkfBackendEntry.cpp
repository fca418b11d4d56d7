#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/ekf/MrptIniKeys.h"

namespace budget_slam::ekf {

BackendEntry EkfBackend::entry() {
  return {kName, "MRPT's range-bearing EKF (CRangeBearingKFSLAM2D), latest pose and landmarks",
          mrptKfSlamIniKeys(),
          [](const mrpt::config::CConfigFileBase& ini, const BackendSettings& settings) {
            auto b = std::make_unique<EkfBackend>(ini);
            b->setKeepTrajectory(settings.keep_trajectory);
            return std::unique_ptr<Backend>(std::move(b));
          }};
}

}  // namespace budget_slam::ekf
