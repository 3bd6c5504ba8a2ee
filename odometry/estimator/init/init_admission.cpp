#include "odometry/estimator/init/init_admission.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace uf::estimator {

AdmissionCheck CheckAdmission(InitMode mode, const InertialAlignment& alignment, std::span<const SE3> poses,
                              std::vector<ImuPreintegration> preintegrations,
                              const InertialInitConfig& config, double gravity) {
  using Verdict = AdmissionCheck::Verdict;
  AdmissionCheck check;
  std::ostringstream why;
  why.precision(3);
  const double tilt_sigma_deg = alignment.tilt_sigma_rad * 180.0 / std::numbers::pi;
  if (mode == InitMode::kLidarAided && !(tilt_sigma_deg <= config.max_tilt_sigma_deg)) {
    why << "gravity direction not yet determined: sigma " << tilt_sigma_deg << " deg > max_tilt_sigma_deg "
        << config.max_tilt_sigma_deg;
    check.verdict = Verdict::kDeferred;
    check.reason = why.str();
    return check;
  }

  const char* estimate = mode == InitMode::kStatic ? "mean specific force " : "estimated gravity ";
  if (!(std::abs(alignment.gravity_estimate - gravity) <= config.max_gravity_error * gravity)) {
    why << estimate << alignment.gravity_estimate << " m/s^2 is not within max_gravity_error "
        << config.max_gravity_error << " of " << gravity;
    check.reason = why.str();
    return check;
  }
  const Eigen::Vector3d g(0, 0, -gravity);
  double chi2 = 0;
  int intervals = 0;
  for (std::size_t k = 0; k + 1 < poses.size() && k < preintegrations.size(); ++k, ++intervals) {
    ImuPreintegration& pre = preintegrations[k];
    pre.Repropagate(alignment.accel_bias, alignment.gyro_bias);
    const Eigen::Matrix3d R_i = alignment.R_gravity_lo.matrix() * poses[k].rotation();
    const Eigen::Vector3d r =
        R_i.transpose() * (alignment.velocities[k + 1] - alignment.velocities[k] - g * pre.sum_dt_seconds()) -
        pre.delta_v();
    chi2 += r.dot(pre.covariance().block<3, 3>(kImuVelocity, kImuVelocity).ldlt().solve(r));
  }
  check.dof = std::max(1, 3 * intervals - 2);  // less the gravity direction fitted to them
  check.chi2_per_dof = chi2 / check.dof;
  if (!(check.chi2_per_dof <= config.max_chi2_per_dof)) {
    why << "the IMU's velocity changes do not fit this state: chi-square " << check.chi2_per_dof
        << " per dof (" << check.dof << " dof) > max_chi2_per_dof " << config.max_chi2_per_dof;
    check.reason = why.str();
    return check;
  }
  check.verdict = Verdict::kAdmitted;
  return check;
}

Eigen::Vector3d GravityDirectionLo(const InertialAlignment& alignment) {
  return alignment.R_gravity_lo.inverse() * Eigen::Vector3d(0, 0, -1);
}

void CheckGravitySettled(const std::optional<Eigen::Vector3d>& before, const Eigen::Vector3d& now,
                         const InertialInitConfig& config, AdmissionCheck& check) {
  if (check.verdict != AdmissionCheck::Verdict::kAdmitted) return;
  const double moved_deg =
      before ? std::acos(std::clamp(before->dot(now), -1.0, 1.0)) * 180.0 / std::numbers::pi : 180.0;
  if (moved_deg <= config.max_tilt_sigma_deg) return;
  std::ostringstream why;
  why.precision(3);
  why << "gravity direction not settled: ";
  if (before)
    why << "the newest scan moved it by " << moved_deg << " deg > max_tilt_sigma_deg "
        << config.max_tilt_sigma_deg;
  else
    why << "no estimate from one scan less to compare with";
  check.verdict = AdmissionCheck::Verdict::kDeferred;
  check.reason = why.str();
}

}  // namespace uf::estimator
