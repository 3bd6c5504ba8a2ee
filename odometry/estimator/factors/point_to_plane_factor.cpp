#include "odometry/estimator/factors/point_to_plane_factor.h"

#include <Eigen/Geometry>
#include <cassert>

#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using RowVector6d = Eigen::Matrix<double, 1, 6>;

Eigen::Matrix3d RotationOfBlock(const double* pose) {
  return Eigen::Map<const Eigen::Quaterniond>(pose + 3).normalized().toRotationMatrix();
}

}  // namespace

PointToPlaneFactor::PointToPlaneFactor(const Eigen::Vector3d& point_lidar, double alpha, const Plane& plane,
                                       const SE3& T_body_lidar)
    : point_body_(T_body_lidar * point_lidar),
      alpha_(alpha),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(alpha >= 0 && alpha <= 1);
  assert(plane.sigma > 0);
}

bool PointToPlaneFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J_b[6], J_e[6];
  double* tangent[2] = {jacobians[0] != nullptr ? J_b : nullptr, jacobians[1] != nullptr ? J_e : nullptr};
  EvaluateTangent(parameters, residuals, tangent);
  if (jacobians[0] != nullptr) TangentToAmbientJacobian(parameters[0], J_b, 1, jacobians[0]);
  if (jacobians[1] != nullptr) TangentToAmbientJacobian(parameters[1], J_e, 1, jacobians[1]);
  return true;
}

bool PointToPlaneFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  const double* pose_b = parameters[0];
  const double* pose_e = parameters[1];
  const Eigen::Map<const Eigen::Vector3d> t_b(pose_b), t_e(pose_e);
  const Eigen::Matrix3d R_b = RotationOfBlock(pose_b);
  const Eigen::Matrix3d R_e = RotationOfBlock(pose_e);
  const Eigen::Vector3d d = SO3(R_b.transpose() * R_e).Log();  // d = Log(R_b^T R_e)
  const Eigen::Vector3d u = alpha_ * d;
  const Eigen::Matrix3d Exp_u = SO3::Exp(u).matrix();
  const Eigen::Matrix3d R_a = R_b * Exp_u;                          // R(a)
  const Eigen::Vector3d t_a = (1.0 - alpha_) * t_b + alpha_ * t_e;  // t(a)
  const Eigen::Vector3d p_w = R_a * point_body_ + t_a;
  residuals[0] = sqrt_information_ * normal_.dot(p_w - plane_point_);
  if (jacobians == nullptr || (jacobians[0] == nullptr && jacobians[1] == nullptr)) return true;

  // dr/dphi for R(a) <- R(a) Exp(phi): -n^T R(a) [p_B]x / sigma.
  const Eigen::RowVector3d dr_dphi = -sqrt_information_ * (normal_.transpose() * R_a) * Hat(point_body_);
  const Eigen::RowVector3d dr_dt = sqrt_information_ * normal_.transpose();
  const Eigen::Matrix3d Jr_u = RightJacobianSO3(u);
  if (jacobians[0] != nullptr) {
    const Eigen::Matrix3d Phi_b = Exp_u.transpose() - alpha_ * Jr_u * LeftJacobianInverseSO3(d);
    Eigen::Map<RowVector6d> J(jacobians[0]);
    J << (1.0 - alpha_) * dr_dt, dr_dphi * Phi_b;
  }
  if (jacobians[1] != nullptr) {
    const Eigen::Matrix3d Phi_e = alpha_ * Jr_u * RightJacobianInverseSO3(d);
    Eigen::Map<RowVector6d> J(jacobians[1]);
    J << alpha_ * dr_dt, dr_dphi * Phi_e;
  }
  return true;
}

PointToPlaneFactorSinglePose::PointToPlaneFactorSinglePose(const Eigen::Vector3d& point_body,
                                                           const Plane& plane)
    : point_body_(point_body),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(plane.sigma > 0);
}

bool PointToPlaneFactorSinglePose::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  if (jacobians == nullptr || jacobians[0] == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J[6];
  double* tangent[1] = {J};
  EvaluateTangent(parameters, residuals, tangent);
  TangentToAmbientJacobian(parameters[0], J, 1, jacobians[0]);
  return true;
}

bool PointToPlaneFactorSinglePose::EvaluateTangent(double const* const* parameters, double* residuals,
                                                   double** jacobians) const {
  const double* pose = parameters[0];
  const Eigen::Map<const Eigen::Vector3d> t(pose);
  const Eigen::Matrix3d R = RotationOfBlock(pose);
  residuals[0] = sqrt_information_ * normal_.dot(R * point_body_ + t - plane_point_);
  if (jacobians == nullptr || jacobians[0] == nullptr) return true;
  Eigen::Map<RowVector6d> J(jacobians[0]);
  J << sqrt_information_ * normal_.transpose(),
      -sqrt_information_ * (normal_.transpose() * R) * Hat(point_body_);
  return true;
}

}  // namespace uf::estimator
