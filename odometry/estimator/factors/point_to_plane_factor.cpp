#include "odometry/estimator/factors/point_to_plane_factor.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using RowVector6d = Eigen::Matrix<double, 1, 6>;

Eigen::Matrix3d RotationOfBlock(const double* pose) {
  return Eigen::Map<const Eigen::Quaterniond>(pose + 3).normalized().toRotationMatrix();
}

// What all points of a scan share at one value of its (begin, end) blocks: the rotations, d = Log(R_b^T R_e)
// and the SO3 Jacobians of d. Solvers evaluate every point of a scan at the same values, so each thread
// keeps the terms of the last pair it saw and recomputes them only when the values change.
struct SweepTerms {
  std::array<double, 2 * kPoseSize> values{};
  bool valid = false;
  Eigen::Matrix3d R_b, R_e, Jl_inv_d, Jr_inv_d;
  Eigen::Vector3d d;
};

const SweepTerms& SweepTermsAt(const double* pose_b, const double* pose_e) {
  thread_local SweepTerms terms;
  if (terms.valid && std::equal(pose_b, pose_b + kPoseSize, terms.values.begin()) &&
      std::equal(pose_e, pose_e + kPoseSize, terms.values.begin() + kPoseSize))
    return terms;
  std::copy(pose_b, pose_b + kPoseSize, terms.values.begin());
  std::copy(pose_e, pose_e + kPoseSize, terms.values.begin() + kPoseSize);
  terms.R_b = RotationOfBlock(pose_b);
  terms.R_e = RotationOfBlock(pose_e);
  terms.d = SO3(terms.R_b.transpose() * terms.R_e).Log();
  terms.Jl_inv_d = LeftJacobianInverseSO3(terms.d);
  terms.Jr_inv_d = RightJacobianInverseSO3(terms.d);
  terms.valid = true;  // (non-finite values never compare equal: they are recomputed every time)
  return terms;
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
  const SweepTerms& sweep = SweepTermsAt(pose_b, pose_e);
  const Eigen::Vector3d u = alpha_ * sweep.d;
  const Eigen::Matrix3d Exp_u = SO3::Exp(u).matrix();
  const Eigen::Matrix3d R_a = sweep.R_b * Exp_u;                    // R(a)
  const Eigen::Vector3d t_a = (1.0 - alpha_) * t_b + alpha_ * t_e;  // t(a)
  const Eigen::Vector3d p_w = R_a * point_body_ + t_a;
  residuals[0] = sqrt_information_ * normal_.dot(p_w - plane_point_);
  if (jacobians == nullptr || (jacobians[0] == nullptr && jacobians[1] == nullptr)) return true;

  // dr/dphi for R(a) <- R(a) Exp(phi): w = -n^T R(a) [p_B]x / sigma; the products with Phi_b and Phi_e
  // are taken row vector first (w Jr(u) is shared).
  const Eigen::RowVector3d w = -sqrt_information_ * (normal_.transpose() * R_a) * Hat(point_body_);
  const Eigen::RowVector3d dr_dt = sqrt_information_ * normal_.transpose();
  const Eigen::RowVector3d w_Jr_u = w * RightJacobianSO3(u);
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowVector6d> J(jacobians[0]);
    J << (1.0 - alpha_) * dr_dt, w * Exp_u.transpose() - alpha_ * w_Jr_u * sweep.Jl_inv_d;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<RowVector6d> J(jacobians[1]);
    J << alpha_ * dr_dt, alpha_ * w_Jr_u * sweep.Jr_inv_d;
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
