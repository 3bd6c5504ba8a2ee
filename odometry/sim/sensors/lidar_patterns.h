// Scan patterns of the simulated LiDARs: the beam elevations of the spinning presets and the Livox-like
// non-repetitive rosette. Lidar frame: x forward, y left, z up; azimuth atan2(y, x), elevation
// atan2(z, hypot(x, y)).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "odometry/types/stamp.h"

namespace uf::sim {

// Elevation of each beam of a spinning LiDAR, ascending: ring r is the r-th lowest beam (ring 0 = lowest).
struct SpinningPattern {
  std::vector<double> elevations_rad;
};

// The preset of "spinning16", "spinning32", "spinning64" or "spinning128"; nullopt for any other name.
std::optional<SpinningPattern> SpinningPatternFor(std::string_view model);

// True for the spinning presets and "livox_avia".
bool IsKnownLidarModel(std::string_view model);

// Livox-like rosette (NOT the exact Avia pattern, whose prism parameters are not public): kLivoxHeads laser
// heads fire in turn, one point every kLivoxPointIntervalNs (~240 k points/s in all), forward-looking
// (+x) over kLivoxHorizontalFovDeg x kLivoxVerticalFovDeg. Point n (a global counter, n = t / interval, so
// the pattern's phase continues across frames and is the same for any frame split) fires at
// t_n = n * kLivoxPointIntervalNs from head n mod kLivoxHeads in the direction LivoxDirection(n).
inline constexpr int kLivoxHeads = 6;
inline constexpr Stamp kLivoxPointIntervalNs = 4167;  // 1e9 / 4167 = 239,981 points/s
inline constexpr double kLivoxHorizontalFovDeg = 70.4;
inline constexpr double kLivoxVerticalFovDeg = 77.2;

// Unit direction of point n in the lidar frame. The pattern: in normalised angle coordinates
// z = (azimuth / half_h_fov) + i (elevation / half_v_fov), each head traces the rose curve
//   z_h(t) = exp(i (2 pi f_rot t + h pi / H)) cos(2 pi f_osc t),   |z| <= 1,
// a line through the centre oscillating at f_osc while it precesses at f_rot; f_osc / f_rot is irrational,
// so the curve never closes and coverage keeps growing with integration time (as a Livox's does). The heads
// are rotated by pi / H from each other so they share the load of sweeping all orientations.
Eigen::Vector3d LivoxDirection(std::int64_t n);

}  // namespace uf::sim
