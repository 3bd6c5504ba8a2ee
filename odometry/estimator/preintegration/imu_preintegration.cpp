#include "odometry/estimator/preintegration/imu_preintegration.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace uf::estimator {
namespace {

bool Finite(const ImuSample& s) { return s.acc.allFinite() && s.gyro.allFinite(); }

// Linear interpolation of two samples at t (a.stamp <= t <= b.stamp, a.stamp < b.stamp).
ImuSample Interpolate(const ImuSample& a, const ImuSample& b, Stamp t) {
  const double s = static_cast<double>(t - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  ImuSample out;
  out.stamp = t;
  out.acc = (1.0 - s) * a.acc + s * b.acc;
  out.gyro = (1.0 - s) * a.gyro + s * b.gyro;
  return out;
}

// The sample at t from sorted samples that cover t: an exact match, or interpolated between neighbours.
ImuSample SampleAt(const std::vector<ImuSample>& samples, Stamp t) {
  const auto after = std::lower_bound(samples.begin(), samples.end(), t,
                                      [](const ImuSample& s, Stamp stamp) { return s.stamp < stamp; });
  if (after->stamp == t) return *after;
  return Interpolate(*(after - 1), *after, t);
}

// Per axis, the standard deviation of a step's unknown clipped excess (header): kClippedExcess * range for
// each end reading at the full scale, halved by the midpoint; zero without a range.
Eigen::Vector3d ClippedExcess(const Eigen::Vector3d& begin, const Eigen::Vector3d& end, double range) {
  Eigen::Vector3d excess = Eigen::Vector3d::Zero();
  if (!(range > 0)) return excess;
  for (int axis = 0; axis < 3; ++axis) {
    const int clipped = (std::abs(begin(axis)) >= range) + (std::abs(end(axis)) >= range);
    excess(axis) = 0.5 * clipped * kClippedExcess * range;
  }
  return excess;
}

}  // namespace

ImuPreintegration::ImuPreintegration(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias,
                                     const ImuNoiseParams& params)
    : params_(params),
      gravity_world_(0.0, 0.0, -params.gravity),
      accel_bias_(accel_bias),
      gyro_bias_(gyro_bias) {
  assert(ValidateImuNoiseParams(params).ok());
  assert(accel_bias.allFinite() && gyro_bias.allFinite());
}

Status ImuPreintegration::Integrate(const ImuSample& begin, const ImuSample& end) {
  if (end.stamp <= begin.stamp) {
    return Status::Error("imu sample: stamps must increase, got " + std::to_string(begin.stamp) + " then " +
                         std::to_string(end.stamp) + " ns");
  }
  if (!Finite(begin) || !Finite(end)) {
    return Status::Error("imu sample: non-finite acc or gyro at stamp " +
                         std::to_string(Finite(begin) ? end.stamp : begin.stamp) + " ns");
  }
  steps_.push_back({begin, end});
  Propagate(steps_.back());
  return Status();
}

Expected<ImuPreintegration> ImuPreintegration::Between(const std::vector<ImuSample>& samples, Stamp t_i,
                                                       Stamp t_j, const Eigen::Vector3d& accel_bias,
                                                       const Eigen::Vector3d& gyro_bias,
                                                       const ImuNoiseParams& params) {
  if (t_j <= t_i) {
    return Status::Error("imu preintegration: t_j must be after t_i, got t_i = " + std::to_string(t_i) +
                         " ns, t_j = " + std::to_string(t_j) + " ns");
  }
  if (samples.empty() || samples.front().stamp > t_i || samples.back().stamp < t_j) {
    return Status::Error("imu preintegration: samples do not cover [" + std::to_string(t_i) + ", " +
                         std::to_string(t_j) + "] ns");
  }
  ImuPreintegration result(accel_bias, gyro_bias, params);
  ImuSample previous = SampleAt(samples, t_i);
  // Samples strictly inside (t_i, t_j), then the end sample.
  auto it = std::upper_bound(samples.begin(), samples.end(), t_i,
                             [](Stamp stamp, const ImuSample& s) { return stamp < s.stamp; });
  for (; it != samples.end() && it->stamp < t_j; ++it) {
    if (Status status = result.Integrate(previous, *it); !status.ok()) return status;
    previous = *it;
  }
  if (Status status = result.Integrate(previous, SampleAt(samples, t_j)); !status.ok()) return status;
  return result;
}

void ImuPreintegration::Repropagate(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) {
  accel_bias_ = accel_bias;
  gyro_bias_ = gyro_bias;
  sum_dt_ = 0;
  clipped_steps_ = 0;
  delta_R_ = SO3();
  delta_v_.setZero();
  delta_p_.setZero();
  bias_jacobian_.setZero();
  covariance_.setZero();
  for (const Step& step : steps_) Propagate(step);
}

void ImuPreintegration::Propagate(const Step& step) {
  const Stamp dt_ns = step.end.stamp - step.begin.stamp;
  const double dt = ToSeconds(dt_ns);
  const double dt2 = dt * dt;

  // Midpoint step (see the header).
  const Eigen::Vector3d w = 0.5 * (step.begin.gyro + step.end.gyro) - gyro_bias_;
  const Eigen::Vector3d a0 = step.begin.acc - accel_bias_;
  const Eigen::Vector3d a1 = step.end.acc - accel_bias_;
  const SO3 dR_step = SO3::Exp(w * dt);
  const Eigen::Matrix3d& R0 = delta_R_.matrix();
  const Eigen::Matrix3d R1 = R0 * dR_step.matrix();
  const Eigen::Vector3d a = 0.5 * (R0 * a0 + R1 * a1);

  // Error-state derivatives of the step, with R(dtheta) = R Exp(dtheta) and measurement noise n_g, n_a:
  //   dtheta1 = dR_step^T dtheta0 - Jr(w dt) dt dbg + Jr(w dt) dt n_g
  //   da      = A_theta dtheta0 + A_ba dba + A_bg dbg + A_ng n_g + A_na n_a, from
  //             d(R a_x) = -R [a_x]x dtheta + R d(a_x) at both ends and dtheta1 above:
  //   A_theta = -(R0 [a0]x + R1 [a1]x dR_step^T) / 2,  A_ba = -(R0 + R1) / 2,
  //   A_bg = R1 [a1]x Jr dt / 2 = -A_ng,  A_na = (R0 + R1) / 2
  //   dv1 = dv0 + da dt,   dp1 = dp0 + dv0 dt + da dt^2 / 2,   dba1 = dba0 + n_ba,   dbg1 = dbg0 + n_bg.
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Jr = RightJacobianSO3(w * dt);
  const Eigen::Matrix3d R1_a1 = R1 * Hat(a1);
  const Eigen::Matrix3d A_theta = -0.5 * (R0 * Hat(a0) + R1_a1 * dR_step.matrix().transpose());
  const Eigen::Matrix3d A_ba = -0.5 * (R0 + R1);
  const Eigen::Matrix3d A_bg = 0.5 * R1_a1 * Jr * dt;

  Matrix15d F = Matrix15d::Identity();
  F.block<3, 3>(kImuRotation, kImuRotation) = dR_step.matrix().transpose();
  F.block<3, 3>(kImuRotation, kImuGyroBias) = -Jr * dt;
  F.block<3, 3>(kImuVelocity, kImuRotation) = A_theta * dt;
  F.block<3, 3>(kImuVelocity, kImuAccelBias) = A_ba * dt;
  F.block<3, 3>(kImuVelocity, kImuGyroBias) = A_bg * dt;
  F.block<3, 3>(kImuPosition, kImuRotation) = 0.5 * dt2 * A_theta;
  F.block<3, 3>(kImuPosition, kImuVelocity) = I * dt;
  F.block<3, 3>(kImuPosition, kImuAccelBias) = 0.5 * dt2 * A_ba;
  F.block<3, 3>(kImuPosition, kImuGyroBias) = 0.5 * dt2 * A_bg;

  // G for n = [n_g, n_a, n_ba, n_bg] and its covariance Q. The white noise of a sample enters two midpoint
  // steps with weight 1/2 each; modelling it as one independent noise of variance density^2 / dt per step
  // gives the same sum over the interval (the continuous-time variance density^2 T).
  Eigen::Matrix<double, 15, 12> G = Eigen::Matrix<double, 15, 12>::Zero();
  G.block<3, 3>(kImuRotation, 0) = Jr * dt;
  G.block<3, 3>(kImuVelocity, 0) = -A_bg * dt;
  G.block<3, 3>(kImuVelocity, 3) = -A_ba * dt;
  G.block<3, 3>(kImuPosition, 0) = -0.5 * dt2 * A_bg;
  G.block<3, 3>(kImuPosition, 3) = -0.5 * dt2 * A_ba;
  G.block<3, 3>(kImuAccelBias, 6) = I;
  G.block<3, 3>(kImuGyroBias, 9) = I;
  Eigen::Matrix<double, 12, 1> q;
  q << Eigen::Vector3d::Constant(params_.gyro_noise_density * params_.gyro_noise_density / dt),
      Eigen::Vector3d::Constant(params_.accel_noise_density * params_.accel_noise_density / dt),
      Eigen::Vector3d::Constant(params_.accel_bias_random_walk * params_.accel_bias_random_walk * dt),
      Eigen::Vector3d::Constant(params_.gyro_bias_random_walk * params_.gyro_bias_random_walk * dt);
  const Eigen::Vector3d gyro_excess = ClippedExcess(step.begin.gyro, step.end.gyro, params_.gyro_range);
  const Eigen::Vector3d accel_excess = ClippedExcess(step.begin.acc, step.end.acc, params_.accel_range);
  q.segment<3>(0) += gyro_excess.cwiseAbs2();
  q.segment<3>(3) += accel_excess.cwiseAbs2();
  if (!gyro_excess.isZero() || !accel_excess.isZero()) ++clipped_steps_;

  const Matrix15d FP = F * covariance_;
  covariance_.noalias() = FP * F.transpose();
  covariance_.noalias() += G * q.asDiagonal() * G.transpose();
  // Only the bias columns of the Jacobian are kept: [J; I] -> F [J; I].
  const Eigen::Matrix<double, 9, 6> J = bias_jacobian_;
  bias_jacobian_.noalias() = F.topLeftCorner<9, 9>() * J;
  bias_jacobian_ += F.topRightCorner<9, 6>();

  delta_p_ += delta_v_ * dt + 0.5 * dt2 * a;
  delta_v_ += a * dt;
  delta_R_ = SO3(R1);
  sum_dt_ += dt_ns;
}

SO3 ImuPreintegration::CorrectedDeltaR(const Eigen::Vector3d& gyro_bias) const {
  return delta_R_ * SO3::Exp(dR_dbg() * (gyro_bias - gyro_bias_));
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaV(const Eigen::Vector3d& accel_bias,
                                                   const Eigen::Vector3d& gyro_bias) const {
  return delta_v_ + dv_dba() * (accel_bias - accel_bias_) + dv_dbg() * (gyro_bias - gyro_bias_);
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaP(const Eigen::Vector3d& accel_bias,
                                                   const Eigen::Vector3d& gyro_bias) const {
  return delta_p_ + dp_dba() * (accel_bias - accel_bias_) + dp_dbg() * (gyro_bias - gyro_bias_);
}

NavState ImuPreintegration::Predict(const NavState& state_i) const {
  const double T = sum_dt_seconds();
  const Eigen::Vector3d g = gravity_world();
  const SO3& R_i = state_i.T_world_imu.so3();
  const Eigen::Vector3d& p_i = state_i.T_world_imu.translation();
  NavState state_j = state_i;
  state_j.stamp = state_i.stamp + sum_dt_;
  // R_j = R_i dR,  v_j = v_i + g T + R_i dv,  p_j = p_i + v_i T + g T^2 / 2 + R_i dp.
  const SO3 R_j = R_i * CorrectedDeltaR(state_i.gyro_bias);
  state_j.velocity = state_i.velocity + g * T + R_i * CorrectedDeltaV(state_i.accel_bias, state_i.gyro_bias);
  const Eigen::Vector3d p_j = p_i + state_i.velocity * T + 0.5 * T * T * g +
                              R_i * CorrectedDeltaP(state_i.accel_bias, state_i.gyro_bias);
  state_j.T_world_imu = SE3(R_j, p_j);
  return state_j;
}

}  // namespace uf::estimator
