#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/ekf/EkfSlamOptions.h"
#include "budget_slam/ekf/MrptIniCheck.h"
#include "budget_slam/ekf/MrptIniKeys.h"

namespace budget_slam::ekf {
namespace {

/// MRPT's kf-slam sections in name order, their keys MRPT's own (no default of ours). One check,
/// on [RangeBearingKFSLAM], covers both filter sections (checkMrptKfSlamOptions). Then ours,
/// [EkfSLAM].
std::vector<OptionSection> kfSlamSections() {
  std::vector<OptionSection> out;
  for (const auto& [section, keys] : mrptKfSlamIniKeys()) {
    OptionSection s{section, keysOnly(keys), {}};
    if (section == "RangeBearingKFSLAM") s.check = checkMrptKfSlamOptions;
    out.push_back(std::move(s));
  }
  out.push_back(tabledSection<EkfSlamOptions>());  // ours: how the update is done
  return out;
}

}  // namespace

BackendEntry EkfBackend::entry() {
  return {kName, "MRPT's range-bearing EKF (CRangeBearingKFSLAM2D), latest pose and landmarks",
          kfSlamSections(),
          [](const mrpt::config::CConfigFileBase& ini, const BackendSettings& settings) {
            auto b = std::make_unique<EkfBackend>(ini);
            b->setKeepTrajectory(settings.keep_trajectory);
            return std::unique_ptr<Backend>(std::move(b));
          }};
}

}  // namespace budget_slam::ekf
