#pragma once
// Bounds on what an input file may claim (docs/RELIABILITY.md "Bounds"): a value beyond them is
// an error naming the file, line or key and the field where it is read, before it reaches a
// filter, a picture or an allocation. Each is far beyond any real planar dataset and well inside
// what the code after the check computes with (MRPT keeps readings as 32-bit floats: 1e6 m still
// has centimetre resolution there).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace budget_slam::limits {

/// |x|, |y| of a position in a map, a ground truth or an alignment [m]: 1000 km.
constexpr double kMaxCoordinate = 1e6;
/// A range reading [m].
constexpr double kMaxRange = 1e5;
/// |bearing| of a reading, |heading| of a pose or a turn [rad]: two turns either way cover any
/// wrapping convention.
constexpr double kMaxAngle = 4 * M_PI;
/// |dx|, |dy| of one odometry step [m]: a ground robot moves less between two frames.
constexpr double kMaxStepTranslation = 1e3;
/// |v| [m/s] and |omega| [rad/s] of a velocity reading.
constexpr double kMaxSpeed = 1e2;
/// |variance| of one entry of a covariance or information matrix (a standard deviation of
/// 1e12, IniSection::kMaxStd) [unit^2].
constexpr double kMaxVariance = 1e24;
/// |t| of a time stamp [s] (the year 2286 in Unix time).
constexpr double kMaxTime = 1e10;
/// A landmark id: MRPT's CObservationBearingRange keeps it as an int32.
constexpr long long kMaxLandmarkId = std::numeric_limits<std::int32_t>::max();
/// The longest line of a text data file [bytes] (the shipped datasets' longest is 107).
constexpr std::size_t kMaxLineBytes = 64 * 1024;
/// Records of one text data file (the largest shipped file holds 63,085).
constexpr std::size_t kMaxRecords = 2'000'000;
/// Steps of one conversion (Victoria Park has 6,969).
constexpr std::size_t kMaxSteps = 500'000;

}  // namespace budget_slam::limits
