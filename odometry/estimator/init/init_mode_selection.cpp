#include "odometry/estimator/init/init_mode_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace uf::estimator {

char InitModeLetter(InitMode mode) {
  switch (mode) {
    case InitMode::kStatic:
      return 'S';
    case InitMode::kLidarAided:
      return 'M';
    case InitMode::kDeferred:
      return 'A';
  }
  return '?';
}

std::string_view InitModeName(InitMode mode) {
  switch (mode) {
    case InitMode::kStatic:
      return "static";
    case InitMode::kLidarAided:
      return "lidar-aided";
    case InitMode::kDeferred:
      return "deferred";
  }
  return "?";
}

InitIndicators ComputeInitIndicators(std::span<const ImuSample> samples, std::span<const Stamp> stamps,
                                     std::span<const SE3> poses, double position_sigma_m, double gravity) {
  InitIndicators out;
  out.imu_samples = static_cast<int>(samples.size());
  if (!samples.empty()) {
    out.imu_span_s = ToSeconds(samples.back().stamp - samples.front().stamp);
    for (const ImuSample& s : samples) {
      out.mean_acc += s.acc;
      out.mean_gyro += s.gyro;
    }
    const double n = static_cast<double>(samples.size());
    out.mean_acc /= n;
    out.mean_gyro /= n;
    double acc_var = 0, gyro_var = 0;
    for (const ImuSample& s : samples) {
      acc_var += (s.acc - out.mean_acc).squaredNorm() / n;
      gyro_var += (s.gyro - out.mean_gyro).squaredNorm() / n;
    }
    out.acc_std = std::sqrt(acc_var);
    out.gyro_std = std::sqrt(gyro_var);
    out.acc_norm_error = std::abs(out.mean_acc.norm() - gravity);
    // Excursions: the deviations from the means integrated sample by sample (rectangle rule).
    Eigen::Vector3d angle = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero();
    for (std::size_t k = 1; k < samples.size(); ++k) {
      const double dt = ToSeconds(samples[k].stamp - samples[k - 1].stamp);
      angle += (samples[k].gyro - out.mean_gyro) * dt;
      velocity += (samples[k].acc - out.mean_acc) * dt;
      out.angle_excursion_rad = std::max(out.angle_excursion_rad, angle.norm());
      out.velocity_excursion_mps = std::max(out.velocity_excursion_mps, velocity.norm());
    }
  }
  // E_v: a straight line through the positions by least squares; its speed less three standard deviations,
  // the noise of a position being position_sigma_m or (LIO) the scatter about the line when larger.
  const std::size_t n = std::min(poses.size(), stamps.size());
  if (n >= 2) {
    double t_mean = 0;
    Eigen::Vector3d p_mean = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      t_mean += ToSeconds(stamps[k] - stamps.front()) / static_cast<double>(n);
      p_mean += poses[k].translation() / static_cast<double>(n);
    }
    double stt = 0;
    Eigen::Vector3d stp = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      const double dt = ToSeconds(stamps[k] - stamps.front()) - t_mean;
      stt += dt * dt;
      stp += dt * (poses[k].translation() - p_mean);
    }
    if (stt > 0) {
      const Eigen::Vector3d velocity = stp / stt;
      double scatter = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const double dt = ToSeconds(stamps[k] - stamps.front()) - t_mean;
        scatter += (poses[k].translation() - p_mean - velocity * dt).squaredNorm();
      }
      double sigma = position_sigma_m;
      if (position_sigma_m > 0 && n > 2) sigma = std::max(sigma, std::sqrt(scatter / (3.0 * (n - 2))));
      out.lo_raw_speed = velocity.norm();
      out.lo_speed = std::max(0.0, velocity.norm() - 3 * sigma / std::sqrt(stt));
    }
  }
  return out;
}

std::string NotStaticReason(const InitIndicators& in, const InertialInitConfig& config, double gravity) {
  constexpr double kDegree = 3.14159265358979323846 / 180.0;
  const double max_vibration_rad = config.static_max_vibration_deg * kDegree;
  std::ostringstream why;
  why.precision(3);
  if (in.imu_span_s < config.static_min_duration_s)
    why << in.imu_span_s << " s of IMU, need static_min_duration_s " << config.static_min_duration_s;
  else if (in.gyro_std > config.static_max_gyro_std && in.angle_excursion_rad > max_vibration_rad)
    why << "angular rate spread " << in.gyro_std << " rad/s > static_max_gyro_std "
        << config.static_max_gyro_std << ", turning the body by " << in.angle_excursion_rad / kDegree
        << " deg > static_max_vibration_deg " << config.static_max_vibration_deg;
  else if (in.acc_std > config.static_max_acc_std && in.velocity_excursion_mps > config.static_max_speed_mps)
    why << "specific force spread " << in.acc_std << " m/s^2 > static_max_acc_std "
        << config.static_max_acc_std << ", changing the velocity by " << in.velocity_excursion_mps
        << " m/s > static_max_speed_mps " << config.static_max_speed_mps;
  else if (in.lo_speed > config.static_max_speed_mps)
    why << "the poses move at " << in.lo_raw_speed << " m/s (" << in.lo_speed
        << " beyond 3 sigma of their noise) > static_max_speed_mps " << config.static_max_speed_mps;
  else if (in.acc_norm_error > config.max_gravity_error * gravity)
    why << "mean specific force " << in.mean_acc.norm() << " m/s^2 is not gravity (" << gravity
        << " within max_gravity_error " << config.max_gravity_error << ")";
  return why.str();
}

ModeDecision SelectInitMode(const InitIndicators& in, const InertialInitConfig& config, double gravity) {
  std::ostringstream why;
  why.precision(3);
  if (in.scans < 2) {
    why << "one scan: no LiDAR motion yet to tell rest from a steady drive";
    return {InitMode::kDeferred, why.str()};
  }
  const std::string not_static = NotStaticReason(in, config, gravity);
  if (not_static.empty()) {
    why << "at rest: angular rate spread " << in.gyro_std << " rad/s, specific force spread " << in.acc_std
        << " m/s^2, LO speed " << in.lo_speed << " m/s over " << in.imu_span_s << " s";
    return {InitMode::kStatic, why.str()};
  }
  if (in.lidar_scans < config.min_scans) {
    why << "not at rest (" << not_static << ") and " << in.lidar_scans << " of the " << in.scans
        << " scans registered past the map's first map_settle_scans, M needs min_scans " << config.min_scans;
    return {InitMode::kDeferred, why.str()};
  }
  why << "moving (" << not_static << "), " << in.lidar_scans << " scans for M";
  return {InitMode::kLidarAided, why.str()};
}

}  // namespace uf::estimator
