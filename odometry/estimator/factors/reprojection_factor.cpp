#include "odometry/estimator/factors/reprojection_factor.h"

#include <cassert>

#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using Matrix26 = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;
using Matrix23 = Eigen::Matrix<double, 2, 3>;

Eigen::Vector3d Homogeneous(const Eigen::Vector2d& u) { return {u.x(), u.y(), 1.0}; }
Eigen::Vector3d Direction(const Eigen::Vector2d& v) { return {v.x(), v.y(), 0.0}; }

}  // namespace

ReprojectionFactor::ReprojectionFactor(const FeatureObservation& anchor, const FeatureObservation& target,
                                       double td_i, double td_j, double sqrt_information,
                                       const SE3& T_target_camera)
    : anchor_(anchor),
      target_(target),
      td_i_(td_i),
      td_j_(td_j),
      sqrt_information_(sqrt_information),
      R_tc_(T_target_camera.so3().matrix()),
      t_tc_(T_target_camera.translation()) {
  assert(sqrt_information > 0);
}

bool ReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  return EvaluateLiftingPoses(*this, 2, 3, 5, parameters, residuals, jacobians);
}

bool ReprojectionFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  const Eigen::Matrix3d R_i = RotationOfPoseBlock(parameters[0]), R_j = RotationOfPoseBlock(parameters[1]);
  const Eigen::Matrix3d R_bc = RotationOfPoseBlock(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> t_i(parameters[0]), t_j(parameters[1]), t_bc(parameters[2]);
  const double lambda = parameters[3][0], td = parameters[4][0];

  // The observations moved to the nodes' times for this t_d.
  const Eigen::Vector2d u_i = anchor_.normalized - (td - td_i_) * anchor_.velocity;
  const Eigen::Vector2d u_j = target_.normalized - (td - td_j_) * target_.velocity;
  const Eigen::Vector3d P_ci = Homogeneous(u_i) / lambda;
  const Eigen::Vector3d P_bi = R_bc * P_ci + t_bc;
  const Eigen::Vector3d P_w = R_i * P_bi + t_i;
  const Eigen::Vector3d P_bj = R_j.transpose() * (P_w - t_j);
  const Eigen::Matrix3d R_cb = R_bc.transpose();
  const Eigen::Vector3d P_cj = R_cb * (P_bj - t_bc);
  const Eigen::Vector3d P_t = R_tc_ * P_cj + t_tc_;  // P_cj itself without a second camera
  const double z = P_t.z();
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = sqrt_information_ * (P_t.head<2>() / z - u_j);
  if (jacobians == nullptr) return true;

  Matrix23 D;
  D << 1 / z, 0, -P_t.x() / (z * z),  //
      0, 1 / z, -P_t.y() / (z * z);
  const Matrix23 sD = sqrt_information_ * D * R_tc_;  // d r / d P_cj
  const Eigen::Matrix3d A = R_cb * R_j.transpose();
  const Eigen::Matrix3d A_Ri_Rbc = A * R_i * R_bc;  // d P_cj / d P_ci
  if (jacobians[0] != nullptr) Eigen::Map<Matrix26>(jacobians[0]) << sD * A, -sD * A * R_i * Hat(P_bi);
  if (jacobians[1] != nullptr) Eigen::Map<Matrix26>(jacobians[1]) << -sD * A, sD * R_cb * Hat(P_bj);
  if (jacobians[2] != nullptr)
    Eigen::Map<Matrix26>(jacobians[2]) << sD * R_cb * (R_j.transpose() * R_i - Eigen::Matrix3d::Identity()),
        sD * (Hat(P_cj) - A_Ri_Rbc * Hat(P_ci));
  if (jacobians[3] != nullptr) {
    Eigen::Map<Eigen::Vector2d> J_lambda(jacobians[3]);
    J_lambda = -sD * A_Ri_Rbc * P_ci / lambda;
  }
  if (jacobians[4] != nullptr) {
    Eigen::Map<Eigen::Vector2d> J_td(jacobians[4]);
    J_td = -sD * A_Ri_Rbc * Direction(anchor_.velocity) / lambda + sqrt_information_ * target_.velocity;
  }
  return true;
}

}  // namespace uf::estimator
