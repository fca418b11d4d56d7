#pragma once
#include "budget_slam/engine/RunDriver.h"
#include "budget_slam/runs/RunConfig.h"

namespace budget_slam::runs {

/// The run driver's specification from a loaded configuration: backend, budget and the
/// [MappingApplication] values the driver acts on.
runs::DriverSpec driverSpec(const RunConfig& rc);

}  // namespace budget_slam::runs
