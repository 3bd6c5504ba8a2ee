// The GNSS receiver's slowly varying error as states of the window (docs/METHOD.md "GNSS factor").
//
// A single-point fix is off by an error that changes over tens of seconds (atmosphere, orbits, multipath),
// plus a little white noise. Fixes at 5 Hz linked as independent measurements average that error as if it
// were white, and the trajectory bends to follow it. Instead, the window carries the error as an offset b
// (ENU, m) per node, a first-order Gauss-Markov process per axis:
//   b_k = a b_{k-1} + w_k,   a = exp(-dt / tau),   w_k ~ N(0, (1 - a^2) diag(s^2))
// with tau the correlation time and s^2 the offset's stationary variance: the share `c` of the fix's
// variance that is correlated, s^2 = c diag(Sigma_fix). The fix keeps the rest as white noise:
//   r = L_w (Rz(yaw) p_w + t + b - f),   L_w = ((1 - c) Sigma_fix)^-1/2   (gnss_factor.h for the rest)
//
// GnssOffsetFactor wraps a GnssFactor or GnssFactorSinglePose built with the white covariance (1 - c)
// Sigma_fix and appends the offset block: r = r_fix + L_w b, dr/db = L_w (the block is Euclidean).
// MakeGnssOffsetProcessFactor, blocks b_{k-1}, b_k:  r_i = (b_k,i - a b_{k-1},i) / (s_i sqrt(1 - a^2)).
// MakeGnssOffsetPrior, block b:  r_i = b_i / s_i, the stationary distribution, for the first offset.
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "odometry/estimator/factors/gnss_factor.h"
#include "odometry/estimator/factors/tangent_jacobian.h"

namespace uf::estimator {

constexpr int kGnssOffsetSize = 3;

class GnssOffsetFactor : public ceres::CostFunction, public TangentJacobianCost {
 public:
  // fix_factor: a GnssFactor or GnssFactorSinglePose made with white_covariance and axes (not null).
  GnssOffsetFactor(std::unique_ptr<ceres::CostFunction> fix_factor, const Eigen::Matrix3d& white_covariance,
                   GnssAxes axes);
  // Blocks: those of the fix factor, then the offset (3).
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  void AddOffset(double const* const* parameters, double* residuals, double** jacobians) const;

  std::unique_ptr<ceres::CostFunction> fix_factor_;
  const TangentJacobianCost* fix_tangent_;  // fix_factor_ as a TangentJacobianCost
  const Eigen::Matrix3d sqrt_information_;  // L_w
  const int offset_index_;                  // the offset's block index: the fix factor's block count
};

// dt_s > 0 between the two offsets' stamps, tau_s > 0, sigma_m: s per axis (finite, > 0). Asserted.
std::unique_ptr<ceres::CostFunction> MakeGnssOffsetProcessFactor(double dt_s, double tau_s,
                                                                 const Eigen::Vector3d& sigma_m);
std::unique_ptr<ceres::CostFunction> MakeGnssOffsetPrior(const Eigen::Vector3d& sigma_m);

}  // namespace uf::estimator
