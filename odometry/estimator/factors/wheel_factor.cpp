#include "odometry/estimator/factors/wheel_factor.h"

#include <Eigen/Cholesky>
#include <cassert>
#include <cmath>
#include <utility>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using RowMajor6x6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

// Upper U with U^T U = covariance^-1 (the information's Cholesky factor, transposed).
Matrix6d SqrtInformation(const Matrix6d& covariance) {
  Matrix6d information = covariance.llt().solve(Matrix6d::Identity());
  information = 0.5 * (information + information.transpose()).eval();
  return information.llt().matrixU();
}

}  // namespace

WheelFactor::WheelFactor(WheelPreintegration preintegration, const SE3& T_imu_wheel)
    : preintegration_(std::move(preintegration)),
      T_imu_wheel_(T_imu_wheel),
      sqrt_information_(SqrtInformation(preintegration_.covariance())) {
  assert(preintegration_.sum_dt() > 0);
  assert(T_imu_wheel.matrix().allFinite());
  assert(sqrt_information_.allFinite());
}

Vector6d WheelFactor::Residual(const double* pose_i, const double* pose_j, double scale,
                               TangentJacobians* jacobians) const {
  const SE3 T_i = PoseFromBlock(pose_i), T_j = PoseFromBlock(pose_j);
  const Eigen::Matrix3d& R_i = T_i.rotation();
  const Eigen::Matrix3d& R_j = T_j.rotation();
  const Eigen::Matrix3d& R_c = T_imu_wheel_.rotation();
  const Eigen::Vector3d& t_c = T_imu_wheel_.translation();
  const Eigen::Vector3d& dp = preintegration_.delta_p();

  // u = R_i^T (p_j + R_j t_c - p_i): the wheel origin at j in the imu frame at i (formulas in the header).
  const Eigen::Matrix3d Rc_T_Ri_T = R_c.transpose() * R_i.transpose();
  const Eigen::Vector3d u = R_i.transpose() * (T_j.translation() + R_j * t_c - T_i.translation());
  const Eigen::Matrix3d R_ij = R_i.transpose() * R_j;
  const Eigen::Matrix3d E = preintegration_.delta_R().matrix().transpose() * R_c.transpose() * R_ij * R_c;
  const Eigen::Vector3d r_R = SO3(E).Log();

  Vector6d r;
  r.segment<3>(kWheelPosition) = R_c.transpose() * (u - t_c) - scale * dp;
  r.segment<3>(kWheelRotation) = r_R;
  if (jacobians == nullptr) return r;

  // Columns: pose [dt 0..2, dtheta 3..5].
  const Eigen::Matrix3d Jr_inv = RightJacobianInverseSO3(r_R);
  auto& Ji = jacobians->pose_i;
  auto& Jj = jacobians->pose_j;
  Ji.setZero();
  Jj.setZero();
  Ji.block<3, 3>(kWheelPosition, 0) = -Rc_T_Ri_T;
  Ji.block<3, 3>(kWheelPosition, 3) = R_c.transpose() * Hat(u);
  Ji.block<3, 3>(kWheelRotation, 3) = -Jr_inv * R_c.transpose() * R_ij.transpose();
  Jj.block<3, 3>(kWheelPosition, 0) = Rc_T_Ri_T;
  Jj.block<3, 3>(kWheelPosition, 3) = -Rc_T_Ri_T * R_j * Hat(t_c);
  Jj.block<3, 3>(kWheelRotation, 3) = Jr_inv * R_c.transpose();
  jacobians->scale.setZero();
  jacobians->scale.segment<3>(kWheelPosition) = -dp;
  return r;
}

bool WheelFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                  double** tangent_jacobians) const {
  const bool want =
      tangent_jacobians != nullptr &&
      (tangent_jacobians[0] != nullptr || tangent_jacobians[1] != nullptr || tangent_jacobians[2] != nullptr);
  TangentJacobians tangent;
  const Vector6d r = Residual(parameters[0], parameters[1], parameters[2][0], want ? &tangent : nullptr);
  const auto U = sqrt_information_.triangularView<Eigen::Upper>();
  Eigen::Map<Vector6d> weighted(residuals);
  weighted = U * r;
  if (!want) return r.allFinite();
  for (int k : {0, 1}) {
    if (tangent_jacobians[k] == nullptr) continue;
    Eigen::Map<RowMajor6x6> J(tangent_jacobians[k]);
    J = U * (k == 0 ? tangent.pose_i : tangent.pose_j);
  }
  if (tangent_jacobians[2] != nullptr) {
    Eigen::Map<Vector6d> J(tangent_jacobians[2]);
    J = U * tangent.scale;
  }
  return r.allFinite();
}

bool WheelFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  RowMajor6x6 J_i, J_j;
  double* tangent[3] = {jacobians[0] != nullptr ? J_i.data() : nullptr,
                        jacobians[1] != nullptr ? J_j.data() : nullptr, jacobians[2]};
  if (!EvaluateTangent(parameters, residuals, tangent)) return false;
  if (jacobians[0] != nullptr) TangentToAmbientJacobian(parameters[0], J_i.data(), 6, jacobians[0]);
  if (jacobians[1] != nullptr) TangentToAmbientJacobian(parameters[1], J_j.data(), 6, jacobians[1]);
  return true;
}

WheelScalePriorFactor::WheelScalePriorFactor(double sigma, double prior)
    : prior_(prior), inverse_sigma_(1.0 / sigma) {
  assert(std::isfinite(sigma) && sigma > 0);
  assert(std::isfinite(prior));
}

bool WheelScalePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  residuals[0] = (parameters[0][0] - prior_) * inverse_sigma_;
  if (jacobians != nullptr && jacobians[0] != nullptr) jacobians[0][0] = inverse_sigma_;
  return std::isfinite(residuals[0]);
}

}  // namespace uf::estimator
