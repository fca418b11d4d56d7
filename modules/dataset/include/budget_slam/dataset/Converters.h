#pragma once
#include <string>
#include <vector>

#include "budget_slam/dataset/ConvertedDataset.h"

namespace budget_slam::dataset {

/// Converters from public planar landmark-SLAM formats (docs/DATASETS.md gives every decision).
/// Each reads any file of its format; a malformed line is an InputError
/// "<file>:<line>: <what is wrong>", a missing file "<file>: cannot open (<reason>)".

/// iSAM / GTSAM text (victoria_park.txt): `ODOMETRY i j dx dy dth` + covariance upper triangle,
/// `LANDMARK i l x y v1 v2 v3` (robot-frame Cartesian sighting of landmark l from pose i, turned
/// into range = hypot(x, y), bearing = atan2(y, x)). The ODOMETRY lines must form one chain; step k
/// is the k-th ODOMETRY line and carries the sightings from its end pose. Sensor noise as GTSAM
/// uses it: std_range = sqrt(v1), std_yaw = sqrt(v1 / 10) (v1 averaged over the file).
/// No ground truth.
ConvertedDataset convertIsam(const std::string& path);

/// 2D g2o: `VERTEX_SE2`, `VERTEX_XY` (initial guesses, ignored), `EDGE_SE2 i j dx dy dth` + the
/// information upper triangle (chain of poses), `EDGE_SE2_XY i l x y` + 2x2 information upper
/// triangle (landmark in the robot frame). Sensor noise: the information propagated to range and
/// bearing, RMS over all sightings. No ground truth.
ConvertedDataset convertG2o(const std::string& path);

/// UTIAS MRCLAM: `folder` holds Barcodes.dat, Landmark_Groundtruth.dat and
/// Robot<robot>_{Odometry,Measurement,Groundtruth}.dat. One step per measurement time with at
/// least one landmark sighting (subjects 1-5 are robots and are left out); odometry (v, omega)
/// integrated exactly between step times. Ground truth (Vicon) expressed in the frame of the
/// robot's true start pose, so that it compares with a filter started at the origin; with
/// `frame_robot` (1-5, 0 = `robot`), in the frame of that robot's true start pose instead, so that
/// the robots of one dataset share one world frame (the path's first row is then not the origin).
ConvertedDataset convertUtias(const std::string& folder, int robot, int frame_robot = 0);

/// Freiburg SLAM course: `world.dat` (`id x y`, landmark ground truth) and `sensor_data.dat`
/// (`ODOMETRY r1 t r2` followed by `SENSOR id range bearing` lines). Noise of the course's EKF
/// exercise.
ConvertedDataset convertFreiburg(const std::string& world, const std::string& sensor_data);

/// Steps `from` (inclusive) to `to` (exclusive, clamped to the end) of a converted dataset,
/// renumbered from 0, with their own times, odometry and readings, and the ground-truth path rows
/// that go with them (the start row: the pose before step `from`); the sensor noise stays the
/// whole dataset's. A note says what was cut. ConfigError when nothing is selected.
ConvertedDataset selectSteps(ConvertedDataset dataset, std::size_t from, std::size_t to);

/// The converter named `format` ("isam", "g2o", "utias", "freiburg") on `inputs`, as
/// budget-convert calls it: isam and g2o take one file; utias one folder (and `robot`); freiburg
/// world.dat and sensor_data.dat, or one folder holding both. An unknown format or a wrong number
/// of inputs is a ConfigError.
ConvertedDataset convertByFormat(const std::string& format, const std::vector<std::string>& inputs,
                                 int robot, int frame_robot = 0);

}  // namespace budget_slam::dataset
