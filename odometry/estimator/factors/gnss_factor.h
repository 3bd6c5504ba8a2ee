// GNSS position factor: a fix of the antenna position, in the ENU frame at the first good fix
// (odometry/estimator/gnss/), ties the window's poses to the Earth through a 4-dof alignment block.
//
// The world is gravity-aligned (LIO: z up), so the world -> ENU transform has only a yaw and a translation:
//   p_enu = Rz(yaw) p_world + t,   alignment block [yaw, t_e, t_n, t_u] (4, Euclidean: no manifold)
//
// GnssFactor, blocks: pose_a, pose_b = T_world_body at the nodes bracketing the fix (nav_state.h layout),
// alignment. With a = (t_fix - t_a) / (t_b - t_a) in [0, 1] and the lever arm l (the antenna in the body
// frame: the translation of T_estimator_body * T_body_gnss, from the calibration):
//   p_w = R(a) l + t(a)                   (slerp / lerp between the two poses, interpolated_point.h)
//   r   = L (Rz(yaw) p_w + t - f)         (f: the fix in ENU, 3 residuals)
//   L   = C^-1, Sigma = C C^T (Cholesky), so r^T r = e^T Sigma^-1 e: the Mahalanobis distance; Sigma is the
//         fix's covariance after the configuration's scale and floor (gnss/fix_screening.h)
// Jacobians in the pose tangents [dt; dtheta] (t <- t + dt, R <- R Exp(dtheta)), lifted to the 7-wide
// ambient blocks with TangentToAmbientJacobian:
//   dr/d(pose_a, pose_b) = L Rz(yaw) dp_w/d(pose_a, pose_b)           (InterpolatedPoint::PullBack)
//   dr/dyaw = L [e_z]x Rz(yaw) p_w = L (-y, x, 0)^T,  (x, y, z) = Rz(yaw) p_w
//   dr/dt   = L
// Ceres rejects a block listed twice in one residual; a fix at a node uses a = 0 with the next node as
// pose_b, or GnssFactorSinglePose.
//
// GnssFactorSinglePose, blocks: pose, alignment: p_w = R l + t_pose, r as above,
//   dr/dt_pose = L Rz(yaw),   dr/dtheta = -L Rz(yaw) R [l]x.
//
// Horizontal only (GnssAxes::kHorizontal: a fix whose height failed the innovation test): L's third row is
// zero. L is lower triangular, so its first two rows whiten exactly the horizontal marginal (e_e, e_n) and
// the factor carries no vertical information.
//
// No robust loss inside: fixes are screened and gated by the innovation test (gnss/integrity_check.h); the
// window may still wrap the factor in a Huber loss.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <array>

#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

constexpr int kGnssAlignmentSize = 4;

// The world -> ENU transform of a gravity-aligned world: p_enu = Rz(yaw) p_world + translation.
struct EnuAlignment {
  double yaw_rad = 0.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d Apply(const Eigen::Vector3d& p_world) const;
  SE3 T_enu_world() const;
};

// The rotation about z by `yaw` (rad).
Eigen::Matrix3d RotationZ(double yaw);

// The alignment block [yaw, t_e, t_n, t_u] and back.
std::array<double, kGnssAlignmentSize> AlignmentBlock(const EnuAlignment& alignment);
EnuAlignment AlignmentFromBlock(const double* block);

enum class GnssAxes { kAll, kHorizontal };  // what a GNSS factor constrains: east, north and up, or not up

// L = C^-1 with covariance = C C^T (its third row zero for kHorizontal); asserts a symmetric positive
// definite covariance.
Eigen::Matrix3d GnssSqrtInformation(const Eigen::Matrix3d& covariance, GnssAxes axes = GnssAxes::kAll);

class GnssFactor : public ceres::SizedCostFunction<3, 7, 7, kGnssAlignmentSize>, public TangentJacobianCost {
 public:
  // fix_enu: the fix in ENU (m); covariance: its 3x3 ENU covariance (m^2, positive definite, asserted);
  // lever_arm: the antenna in the body frame (m); alpha in [0, 1] (asserted).
  GnssFactor(const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& covariance,
             const Eigen::Vector3d& lever_arm, double alpha, GnssAxes axes = GnssAxes::kAll);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Jacobians 3 x 6 for the poses (the tangents [dt; dtheta]) and 3 x 4 for the alignment, row-major.
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d fix_enu_;           // f
  const Eigen::Matrix3d sqrt_information_;  // L
  const Eigen::Vector3d lever_arm_;         // l
  const double alpha_;
};

class GnssFactorSinglePose : public ceres::SizedCostFunction<3, 7, kGnssAlignmentSize>,
                             public TangentJacobianCost {
 public:
  GnssFactorSinglePose(const Eigen::Vector3d& fix_enu, const Eigen::Matrix3d& covariance,
                       const Eigen::Vector3d& lever_arm, GnssAxes axes = GnssAxes::kAll);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d fix_enu_;
  const Eigen::Matrix3d sqrt_information_;
  const Eigen::Vector3d lever_arm_;
};

}  // namespace uf::estimator
