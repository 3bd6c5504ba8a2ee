#include "odometry/estimator/factors/imu_factor.h"

#include <Eigen/Cholesky>
#include <cassert>
#include <utility>

#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

// Upper U with U^T U = covariance^-1 (the information's Cholesky factor, transposed).
Matrix15d SqrtInformation(const Matrix15d& covariance) {
  Matrix15d information = covariance.llt().solve(Matrix15d::Identity());
  information = 0.5 * (information + information.transpose()).eval();
  return information.llt().matrixU();
}

Eigen::Vector3d Segment(const double* x) { return Eigen::Vector3d(x[0], x[1], x[2]); }

// The residual and tangent Jacobians of imu_factor.h for one preintegration (linearized at b_lin).
Vector15d ResidualOf(const ImuPreintegration& pre, const double* pose_i, const double* speed_bias_i,
                     const double* pose_j, const double* speed_bias_j,
                     ImuFactor::TangentJacobians* jacobians) {
  const SE3 T_i = PoseFromBlock(pose_i), T_j = PoseFromBlock(pose_j);
  const Eigen::Matrix3d& R_i = T_i.rotation();
  const Eigen::Matrix3d& R_j = T_j.rotation();
  const Eigen::Vector3d v_i = Segment(speed_bias_i), v_j = Segment(speed_bias_j);
  const Eigen::Vector3d ba_i = Segment(speed_bias_i + 3), bg_i = Segment(speed_bias_i + 6);
  const Eigen::Vector3d ba_j = Segment(speed_bias_j + 3), bg_j = Segment(speed_bias_j + 6);
  const double T = pre.sum_dt_seconds();
  const Eigen::Vector3d g = pre.gravity_world();

  // dR(bg_i) = dR Exp(phi_b), phi_b = dR/dbg (bg_i - bg_lin); E = dR(bg_i)^T R_i^T R_j.
  const Eigen::Vector3d phi_b = pre.dR_dbg() * (bg_i - pre.gyro_bias());
  const Eigen::Matrix3d dR_corrected = pre.delta_R().matrix() * SO3::Exp(phi_b).matrix();
  const Eigen::Matrix3d E = dR_corrected.transpose() * R_i.transpose() * R_j;
  const Eigen::Vector3d r_R = SO3(E).Log();
  const Eigen::Vector3d a = R_i.transpose() * (v_j - v_i - g * T);
  const Eigen::Vector3d b =
      R_i.transpose() * (T_j.translation() - T_i.translation() - v_i * T - 0.5 * T * T * g);

  Vector15d r;
  r.segment<3>(kImuRotation) = r_R;
  r.segment<3>(kImuVelocity) = a - pre.CorrectedDeltaV(ba_i, bg_i);
  r.segment<3>(kImuPosition) = b - pre.CorrectedDeltaP(ba_i, bg_i);
  r.segment<3>(kImuAccelBias) = ba_j - ba_i;
  r.segment<3>(kImuGyroBias) = bg_j - bg_i;
  if (jacobians == nullptr) return r;

  // Columns: pose [dt 0..2, dtheta 3..5], speed_bias [v 0..2, ba 3..5, bg 6..8] (formulas in the header).
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Jr_inv = RightJacobianInverseSO3(r_R);
  const Eigen::Matrix3d Ri_T = R_i.transpose();
  auto& Jpi = jacobians->pose_i;
  auto& Jsi = jacobians->speed_bias_i;
  auto& Jpj = jacobians->pose_j;
  auto& Jsj = jacobians->speed_bias_j;
  Jpi.setZero();
  Jsi.setZero();
  Jpj.setZero();
  Jsj.setZero();

  Jpi.block<3, 3>(kImuRotation, 3) = -Jr_inv * R_j.transpose() * R_i;
  Jpi.block<3, 3>(kImuVelocity, 3) = Hat(a);
  Jpi.block<3, 3>(kImuPosition, 0) = -Ri_T;
  Jpi.block<3, 3>(kImuPosition, 3) = Hat(b);

  Jsi.block<3, 3>(kImuRotation, 6) = -Jr_inv * E.transpose() * RightJacobianSO3(phi_b) * pre.dR_dbg();
  Jsi.block<3, 3>(kImuVelocity, 0) = -Ri_T;
  Jsi.block<3, 3>(kImuVelocity, 3) = -pre.dv_dba();
  Jsi.block<3, 3>(kImuVelocity, 6) = -pre.dv_dbg();
  Jsi.block<3, 3>(kImuPosition, 0) = -Ri_T * T;
  Jsi.block<3, 3>(kImuPosition, 3) = -pre.dp_dba();
  Jsi.block<3, 3>(kImuPosition, 6) = -pre.dp_dbg();
  Jsi.block<3, 3>(kImuAccelBias, 3) = -I;
  Jsi.block<3, 3>(kImuGyroBias, 6) = -I;

  Jpj.block<3, 3>(kImuRotation, 3) = Jr_inv;
  Jpj.block<3, 3>(kImuPosition, 0) = Ri_T;

  Jsj.block<3, 3>(kImuVelocity, 0) = Ri_T;
  Jsj.block<3, 3>(kImuAccelBias, 3) = I;
  Jsj.block<3, 3>(kImuGyroBias, 6) = I;
  return r;
}

}  // namespace

ImuFactor::ImuFactor(ImuPreintegration preintegration)
    : preintegration_(std::move(preintegration)),
      sqrt_information_(SqrtInformation(preintegration_.covariance())) {
  assert(preintegration_.sum_dt() > 0);
}

bool ImuFactor::NeedsRepropagation(const Eigen::Vector3d& accel_bias,
                                   const Eigen::Vector3d& gyro_bias) const {
  const ImuNoiseParams& params = preintegration_.params();
  return (accel_bias - preintegration_.accel_bias()).norm() > params.max_accel_bias_change ||
         (gyro_bias - preintegration_.gyro_bias()).norm() > params.max_gyro_bias_change;
}

Vector15d ImuFactor::Residual(const double* pose_i, const double* speed_bias_i, const double* pose_j,
                              const double* speed_bias_j, TangentJacobians* jacobians) const {
  const Eigen::Vector3d ba_i = Segment(speed_bias_i + 3), bg_i = Segment(speed_bias_i + 6);
  if (!NeedsRepropagation(ba_i, bg_i)) {
    return ResidualOf(preintegration_, pose_i, speed_bias_i, pose_j, speed_bias_j, jacobians);
  }
  ImuPreintegration local = preintegration_;
  local.Repropagate(ba_i, bg_i);
  return ResidualOf(local, pose_i, speed_bias_i, pose_j, speed_bias_j, jacobians);
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const bool want_jacobians = jacobians != nullptr;
  TangentJacobians tangent;
  const Vector15d r = Residual(parameters[0], parameters[1], parameters[2], parameters[3],
                               want_jacobians ? &tangent : nullptr);
  Eigen::Map<Vector15d> weighted_residual(residuals);
  weighted_residual = sqrt_information_.triangularView<Eigen::Upper>() * r;
  if (!want_jacobians) return true;

  using RowMajor15x6 = Eigen::Matrix<double, 15, 6, Eigen::RowMajor>;
  using RowMajor15x9 = Eigen::Matrix<double, 15, 9, Eigen::RowMajor>;
  const auto U = sqrt_information_.triangularView<Eigen::Upper>();
  for (int k : {0, 2}) {
    if (jacobians[k] == nullptr) continue;
    const RowMajor15x6 weighted = U * (k == 0 ? tangent.pose_i : tangent.pose_j);
    TangentToAmbientJacobian(parameters[k], weighted.data(), 15, jacobians[k]);
  }
  for (int k : {1, 3}) {
    if (jacobians[k] == nullptr) continue;
    Eigen::Map<RowMajor15x9> J(jacobians[k]);
    J = U * (k == 1 ? tangent.speed_bias_i : tangent.speed_bias_j);
  }
  return true;
}

bool ImuFactor::Relinearize(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) {
  if (!NeedsRepropagation(accel_bias, gyro_bias)) return false;
  preintegration_.Repropagate(accel_bias, gyro_bias);
  sqrt_information_ = SqrtInformation(preintegration_.covariance());
  return true;
}

}  // namespace uf::estimator
