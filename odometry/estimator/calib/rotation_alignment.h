// The LiDAR-IMU rotation from pairs of rates (docs/METHOD.md, "Online spatiotemporal calibration"): the IMU
// sees the LiDAR's rotation rate turned into its own frame, plus its gyro bias,
//
//   w_I,k = R_IL w_L,k + b_g + noise.
//
// FitRotation solves  min_{R, b}  sum_k w_k ||R a_k + b - c_k||^2  (a = w_L, c = w_I) in closed form: with
// the weighted means a_bar, c_bar, the cross-covariance H = sum_k w_k (a_k - a_bar)(c_k - c_bar)^T = U S V^T
// gives R = V diag(1, 1, det(V U^T)) U^T (Kabsch/Umeyama, a proper rotation) and b = c_bar - R a_bar.
// FitRotationRobust repeats it with Huber weights on the residual norms (IRLS), the threshold
// k = max(k_min, 3 sigma) with sigma = median |r| / 1.538 (the median of a 3-D Gaussian residual's norm is
// 1.538 sigma), so that the rates' own noise is never mistaken for outliers.
//
// Only the variation of w_L about its mean constrains R: RotationExcitation measures it as the eigenvalues of
// M = sum_k w_k u_k u_k^T with u_k = (a_k - a_bar) / |a_k - a_bar|, a scatter of axes; a motion about one
// axis (a car that only turns) leaves R free about that axis and gives lambda_min / lambda_max ~ 0.
#pragma once

#include <Eigen/Core>
#include <span>

#include "odometry/types/so3.h"

namespace uf::estimator {

struct RatePair {
  Eigen::Vector3d lidar = Eigen::Vector3d::Zero();  // w_L, rad/s, LiDAR frame
  Eigen::Vector3d imu = Eigen::Vector3d::Zero();    // w_I, rad/s, IMU frame
  double weight = 1.0;
};

struct RotationFit {
  SO3 R_imu_lidar;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  double rms_residual = 0.0;  // rad/s, weighted, over the inliers
  double inlier_ratio = 1.0;  // share of pairs with a residual within the Huber threshold (1 without one)
  double huber_rad_s = 0.0;   // the threshold used (0 without one)
};

// The closed-form weighted fit (see the top of this file). Needs at least 3 pairs with positive weight.
RotationFit FitRotation(std::span<const RatePair> pairs);

// FitRotation with Huber weights (see the top of this file; min_huber_rad_s is k_min), `iterations`
// reweightings.
RotationFit FitRotationRobust(std::span<const RatePair> pairs, double min_huber_rad_s, int iterations = 5);

// The largest standard deviation (rad) of the fitted rotation over its three axes: with the perturbation
// R <- Exp(d) R, the residual's Jacobian for pair k is -[R (a_k - a_bar)]x, so
//   Cov(d) = sigma^2 (sum_k w_k [R a'_k]x^T [R a'_k]x)^-1 * overlap,   sigma^2 = rms_residual^2 / 3
// (the residual's variance per axis); `overlap` (>= 1) is how many pairs share each stretch of data (pairs
// over sliding spans are not independent). Infinite when the information matrix is singular.
double RotationSigma(std::span<const RatePair> pairs, const RotationFit& fit, double overlap);

struct RotationExcitation {
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  // of M, ascending, normalised to sum 1
  double ratio = 0.0;                                     // lambda_min / lambda_max
  double rate_spread_rad_s = 0.0;  // weighted RMS of |a_k - a_bar|: how much the rate varied
};

RotationExcitation MeasureRotationExcitation(std::span<const RatePair> pairs);

}  // namespace uf::estimator
