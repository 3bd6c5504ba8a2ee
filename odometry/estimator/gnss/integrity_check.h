// The innovation (integrity) test of a GNSS fix before its factor enters the window: a fix far from where
// the window predicts the antenna (multipath, a wrong fix) is left out instead of pulling the trajectory.
//
//   e   = Rz(yaw) p_pred + t - f            (p_pred: predicted antenna in the world; f: the fix in ENU)
//   d^2 = e^T (Sigma_fix + s_p^2 I)^-1 e    (Sigma_fix: FixCovariance)
//   s_p^2 = prediction_sigma_m^2 + (prediction_drift_fraction d)^2   (d: distance since the last accepted
//   fix) accepted iff d^2 <= config.integrity_gate
// For Gaussian errors of those covariances d^2 is chi-square with 3 degrees of freedom, so the default gate
// 16.27 rejects 0.1 % of good fixes.
#pragma once

#include <Eigen/Core>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/factors/gnss_factor.h"

namespace uf::estimator {

struct IntegrityResult {
  bool accepted = false;
  double d2 = 0.0;                                       // the squared Mahalanobis distance (for logging)
  Eigen::Vector3d innovation = Eigen::Vector3d::Zero();  // e, m
};

// `distance_m`: how far the antenna moved since the last accepted fix. A non-finite input gives accepted
// false and d2 = infinity.
IntegrityResult CheckIntegrity(const Eigen::Vector3d& antenna_world_predicted, const EnuAlignment& alignment,
                               const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& fix_covariance,
                               double distance_m, const GnssFactorConfig& config);

}  // namespace uf::estimator
