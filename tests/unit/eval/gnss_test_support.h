// Shared by the GNSS alignment and georeference tests: a drive placed in an ENU frame by a known
// T_enu_world, the fixes a receiver on it reports (position plus Gaussian noise, with that covariance), and
// where an alignment puts a point, in the true ENU frame.
#pragma once

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "odometry/eval/gnss_alignment.h"
#include "odometry/types/geodetic.h"
#include "odometry/types/measurements.h"
#include "odometry/types/trajectory.h"

namespace uf::testing {

constexpr Stamp kSecond = 1'000'000'000;
inline const GeodeticOrigin kTrueOrigin{48.137, 11.575, 520.0};  // the fixes' true ENU frame

// 30 s along an S-curve at ~4 m/s with some climb, in a world frame whose z is up.
inline Trajectory Drive() {
  Trajectory trajectory;
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.1 * k, yaw = 0.4 * std::sin(0.2 * t);
    trajectory.stamps.push_back(k * kSecond / 10);
    trajectory.poses.emplace_back(SO3::Exp(Eigen::Vector3d(0, 0, yaw)),
                                  Eigen::Vector3d(4 * t, 8 * std::sin(0.15 * t), 0.05 * t));
  }
  return trajectory;
}

// Fixes at every `every`-th pose (5 Hz for 2) of an antenna at `antenna` in the trajectory's body frame,
// placed in ENU at kTrueOrigin by T_enu_world, with Gaussian noise of sigma_m(pose index) per axis and the
// covariance sigma^2 I (at least 1 cm^2).
inline std::vector<GnssFix> Fixes(const Trajectory& trajectory, const SE3& T_enu_world,
                                  const Eigen::Vector3d& antenna,
                                  const std::function<double(std::size_t)>& sigma_m, int every = 2) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<GnssFix> fixes;
  for (std::size_t k = 0; k < trajectory.size(); k += static_cast<std::size_t>(every)) {
    const double sigma = sigma_m(k);
    Eigen::Vector3d enu = T_enu_world * (trajectory.poses[k] * antenna);
    for (int axis = 0; axis < 3; ++axis) enu[axis] += sigma * noise(rng);
    const Eigen::Vector3d geodetic = GeodeticFromEnu(kTrueOrigin, enu);
    GnssFix fix;
    fix.stamp = trajectory.stamps[k];
    fix.latitude_deg = geodetic.x();
    fix.longitude_deg = geodetic.y();
    fix.altitude_m = geodetic.z();
    fix.covariance_enu = Eigen::Matrix3d::Identity() * std::max(sigma * sigma, 1e-4);
    fix.status = GnssFixStatus::kRtkFixed;
    fixes.push_back(fix);
  }
  return fixes;
}

// The world point p_world as the alignment places it, in the true ENU frame (through WGS84, since the
// alignment's ENU frame sits at its first fix).
inline Eigen::Vector3d AlignedInTrueEnu(const GnssAlignment& aligned, const Eigen::Vector3d& p_world) {
  return EnuFromGeodetic(kTrueOrigin, GeodeticFromEnu(aligned.origin, aligned.T_enu_world * p_world));
}

}  // namespace uf::testing
