// The innovation (integrity) test of a GNSS fix before its factor enters the window: a fix far from where
// the window predicts the antenna (multipath, a wrong fix) is left out instead of pulling the trajectory.
//
//   e     = Rz(yaw) p_pred + t - f          (p_pred: predicted antenna in the world; f: the fix in ENU)
//   d^2   = e^T (Sigma_fix + s_p^2 I)^-1 e  (Sigma_fix: FixCovariance)
//   s_p^2 = prediction_sigma_m^2 + (prediction_drift_fraction d)^2
//           (d: the distance the antenna moved since the last accepted fix)
//   accepted iff d^2 <= config.integrity_gate
// For Gaussian errors of those covariances d^2 is chi-square with 3 degrees of freedom, so the default gate
// 16.27 rejects 0.1 % of good fixes.
//
// The horizontal and the vertical part are also tested on their own, at the same tail probability (13.82
// for 2 dof and 10.83 for 1 dof at the default): with S = C C^T (Cholesky, ENU order) and w = C^-1 e,
// w_e^2 + w_n^2 is the horizontal Mahalanobis distance and w_u^2 the vertical one given the horizontal.
// Receivers' heights are often off by far more than their reported sigma (tens of metres over minutes on
// the Husky), so a fix whose height fails while its position passes is used horizontally
// (horizontal_accepted) instead of being lost.
#pragma once

#include <Eigen/Core>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/estimator/factors/gnss_factor.h"

namespace uf::estimator {

struct IntegrityResult {
  bool accepted = false;             // all three axes
  bool horizontal_accepted = false;  // east and north (accepted implies it)
  double d2 = 0.0;                   // the squared Mahalanobis distance (for logging)
  double d2_horizontal = 0.0, d2_vertical = 0.0;
  Eigen::Vector3d innovation = Eigen::Vector3d::Zero();  // e, m
};

// P(chi-square_dof > x), dof 1, 2 or 3.
double ChiSquareTail(double x, int dof);
// The value x with P(chi-square_dof > x) = tail, dof 1, 2 or 3.
double ChiSquareQuantile(double tail, int dof);

// `distance_m`: how far the antenna moved since the last accepted fix. A non-finite input gives accepted
// false and d2 = infinity.
IntegrityResult CheckIntegrity(const Eigen::Vector3d& antenna_world_predicted, const EnuAlignment& alignment,
                               const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& fix_covariance,
                               double distance_m, const GnssFactorConfig& config);

}  // namespace uf::estimator
