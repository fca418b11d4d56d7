#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/engine/FinalRelocCoverage.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/report/Pictures.h"

namespace budget_slam::runs {

/// What map.png and map.3Dscene show of a run (docs/OUTPUTS.md): `title`, the path, the kept
/// landmarks coloured by coverage clusters of their observation positions (k-means with
/// `clusters`: the run's [CoverageReducer] settings and seed, whatever the reducer), the drop
/// positions, the ground truth in the estimate's frame (`truth` may be null) and, with
/// `coverage`, the path coloured by the final map's landmarks in view.
report::MapContent runMapContent(std::string title, const std::vector<TrajectoryPoint>& trajectory,
                                 const std::vector<LandmarkView>& landmarks,
                                 const reducers::CoverageOptions& clusters,
                                 const std::vector<Eigen::Vector2d>& dropped,
                                 const FinalRelocCoverage* coverage,
                                 const dataset::GroundTruth* truth);

}  // namespace budget_slam::runs
