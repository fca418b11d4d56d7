#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"

namespace budget_slam::report {

/// Reads a run's landmarks.csv (the layout writeLandmarksCsv writes) back: the map that
/// `budget-slam localize` starts from. Every failure is one InputError line naming the file (and
/// line): a missing file, a header that is not the one written, a row with the wrong number of
/// cells, a value that is not a finite number, an id that is not a non-negative integer or appears
/// twice, a covariance that is not positive semi-definite, more than `max_rows` landmarks.
std::vector<LandmarkView> readLandmarksCsv(const std::string& path, std::size_t max_rows);

/// Reads a trajectory.tum (`t x y z qx qy qz qw`; the rotation taken as a yaw about z): strictly
/// increasing times, finite numbers, at most `max_rows` poses. `step` of each point is its row.
/// Errors as above.
std::vector<TrajectoryPoint> readTrajectoryTum(const std::string& path, std::size_t max_rows);

}  // namespace budget_slam::report
