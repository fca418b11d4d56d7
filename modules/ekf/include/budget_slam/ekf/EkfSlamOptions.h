#pragma once
#include "budget_slam/core/OptionTable.h"

namespace budget_slam::ekf {

/// [EkfSLAM]: how the EKF does MRPT's filter arithmetic, the mapping filter (EKF backend) and the
/// relocalization filter (localize, compare --relocalize) alike: RangeBearingKF2D
/// (docs/ARCHITECTURE.md "EKF backend"); MRPT's own keys stay in [RangeBearingKFSLAM] and
/// [RangeBearingKFSLAM_KalmanFilter].
/// One table (table()): loading, the dump and the unknown-key check follow from it.
struct EkfSlamOptions : public TabledOptions<EkfSlamOptions> {
  static constexpr const char* kSection = "EkfSLAM";

  /// The Kalman update of a step.
  enum class Update {
    /// Only the robot's 3 and each observed landmark's 2 columns of the observation Jacobian H
    /// are used: P Hᵀ from those rows of P, the gain from it, P -= K (H P) on one triangle
    /// (O(n² m) for n state entries and m readings). Equal to `mrpt` up to round-off
    /// (docs/PERFORMANCE.md "EKF update": 1e-9 on every tested rawlog). Used for MRPT's
    /// kfEKFNaive and kfIKFFull with analytic Jacobians; any other
    /// [RangeBearingKFSLAM_KalmanFilter]
    /// setting runs MRPT's own update.
    Sparse,
    /// MRPT's own iteration (CKalmanFilterCapable::runOneKalmanIteration): the dense H of the
    /// whole state and P <- (I - K H) P, O(n³) a step; the result of MRPT's kf-slam.
    Mrpt
  };
  Update update = Update::Sparse;  ///< default: sparse

  static const OptionTable<EkfSlamOptions>& table();
  static const EnumNames<Update>& updateNames();
};

}  // namespace budget_slam::ekf
