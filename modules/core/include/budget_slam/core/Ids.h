#pragma once
#include <cstddef>
#include <cstdint>

namespace budget_slam {

/// Landmark identifier: the sensor's landmark ID when the rawlog carries one, otherwise a fresh
/// id handed out by the backend (never reused, see docs/ARCHITECTURE.md "EKF backend").
using LandmarkId = std::int64_t;

/// Marks a reading that carries no sensor landmark ID (MRPT uses negative IDs for that).
constexpr LandmarkId kNoLandmarkId = -1;

/// 0-based index of an action-observation pair in the rawlog.
using StepIndex = std::size_t;

}  // namespace budget_slam
