#pragma once
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Pose2.h"

namespace budget_slam::dataset {

/// Ground truth in MRPT's simul-landmarks formats (docs/ARCHITECTURE.md "Outputs"):
///  - `<rawlog>_ground_truth.txt`: one landmark a row, x y z in columns 0-2, id in column 6;
///  - `<rawlog>_ground_truth_robot_path.txt`: one row a step, `x y z yaw pitch roll`.
struct GroundTruth {
  std::map<LandmarkId, Eigen::Vector2d> landmarks;  ///< [m]
  std::vector<Pose2> path;                          ///< one pose a step, empty when absent
  std::string landmarks_file, path_file;            ///< where they came from ("" if absent)
  bool empty() const { return landmarks.empty() && path.empty(); }
};

/// `<dir>/<stem>_ground_truth.txt` and `<dir>/<stem>_ground_truth_robot_path.txt` next to a
/// rawlog named `<dir>/<stem>.rawlog`.
std::string groundTruthLandmarksPathFor(const std::string& rawlog);
std::string groundTruthRobotPathFor(const std::string& rawlog);

/// Loads the files that exist; an explicit file name that does not exist or does not parse is an
/// InputError naming the file and line. Empty names mean "look next to the rawlog".
GroundTruth loadGroundTruth(const std::string& rawlog, const std::string& landmarks_file = "",
                            const std::string& path_file = "");

/// The texts of the two files, in the formats loadGroundTruth reads (simul-landmarks' own).
/// A landmark id that does not fit MRPT's int is an InputError.
std::string groundTruthLandmarksText(const std::map<LandmarkId, Eigen::Vector2d>& landmarks);
std::string groundTruthPathText(const std::vector<Pose2>& path);

/// The texts written to `file` (atomically, core/FileWrite.h).
void saveGroundTruthLandmarks(const std::string& file,
                              const std::map<LandmarkId, Eigen::Vector2d>& landmarks);
void saveGroundTruthPath(const std::string& file, const std::vector<Pose2>& path);

}  // namespace budget_slam::dataset
