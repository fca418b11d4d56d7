#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "../TextTable.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/SensorNoise.h"

namespace budget_slam::dataset::convert {

/// The file name without its folders (notes name inputs so, so that the output does not depend on
/// where the input was read from).
std::string baseName(const std::string& path);

/// Symmetric matrix from the upper triangle stored row by row in fields first, first+1, ... of the
/// current record; each entry a finite number of at most limits::kMaxVariance.
Eigen::Matrix3d upperTriangle3(const TextTable& t, std::size_t first, const std::string& what);
Eigen::Matrix2d upperTriangle2(const TextTable& t, std::size_t first, const std::string& what);

/// Fails on the current record unless m is positive semi-definite (positive definite when
/// `strict`).
void checkCovariance(const TextTable& t, const Eigen::MatrixXd& m, const std::string& what,
                     bool strict);

/// The covariance of an information matrix (positive definite, checked before): fails on the
/// current record when its inverse is not finite or beyond limits::kMaxVariance.
Eigen::MatrixXd covarianceOfInformation(const TextTable& t, const Eigen::MatrixXd& info);

/// Throws InputError naming `file` unless the sensor noise a converter made from it is one
/// budget-slam accepts (std_range, std_yaw from IniSection::kMinStd to kMaxStd).
void checkSensorNoise(const SensorNoise& noise, const std::string& file);

/// An empty scan of the sensor `noise` describes.
RangeBearingScan emptyScan(const SensorNoise& noise);

/// Range and bearing limits of a sensor whose file states none: min_range 0, max_range the
/// longest reading, fov_yaw twice the largest absolute bearing (at most 2 pi).
void limitsFromReadings(const std::vector<RangeBearingReading>& readings, SensorNoise& noise);

}  // namespace budget_slam::dataset::convert
