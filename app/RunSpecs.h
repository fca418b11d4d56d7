#pragma once
#include "RunConfig.h"
#include "budget_slam/runs/RunDriver.h"

namespace budget_slam::app {

/// The run driver's specification from a loaded configuration: backend, budget and the
/// [MappingApplication] values the driver acts on.
runs::DriverSpec driverSpec(const RunConfig& rc);

}  // namespace budget_slam::app
