// Observability-aware choice of the initialization mode of LIO (docs/METHOD.md "Observability-aware
// initialization"; paper Sec. III-C, Algorithm 1), from the first measurements: the IMU samples of the
// initialization window and the LO poses of its scans.
//
// The LO poses are taken at the middle of each scan: a registration fixes the scan's mean position well,
// its motion within the sweep (the deskew) poorly: at rest the begin and end nodes of a 16-beam scan scatter
// by 1-2 cm in opposite directions, their mean by 2-4 mm.
//
// Indicators (InitIndicators):
//   E_omega = spread of the angular rate (RMS of the 3D deviation from the mean), rad/s: angular excitation;
//   E_a     = spread of the specific force, m/s^2, and ||mean specific force| - gravity|: linear excitation
//   as
//             the IMU sees it (a steady velocity is invisible to it);
//   E_v     = the LO speed beyond its noise: |v| - 3 sigma_v, at least 0, with v the slope of a straight line
//             fitted to the scan middles' positions p_k(t_k) by least squares, sigma_v = sigma_p /
//             sqrt(sum (t_k - mean t)^2) and sigma_p the larger of lidar_position_sigma_m and the scatter
//             about the line (the LO's noise differs by scene: 2-4 mm between the first scans in the
//             simulated streets, 1-4 cm on the rough wild terrain): linear excitation as the LiDAR sees it;
//   N_lidar = the registered scans of the window (or the first of a map): LiDAR support; a scan whose
//             registration was rejected has only a predicted pose.
// Decision (SelectInitMode):
//   S (static) when the IMU has rested for static_min_duration_s, E_omega <= static_max_gyro_std,
//     E_a <= static_max_acc_std and E_v <= static_max_speed_mps (with two scans at least: a static IMU looks
//     the same as a steady drive, which only the LiDAR tells apart). A spread above its limit still counts as
//     rest when it is vibration: the body's rate less its mean, integrated, turns it by at most
//     static_max_vibration_deg, and its specific force less the mean, integrated, changes its velocity by at
//     most static_max_speed_mps (a MAV whose rotors run, a car with its engine idling);
//   M (LiDAR-aided short-window MAP) when not at rest and N_lidar >= min_scans;
//     M itself then defers while its gravity direction is not yet determined to max_tilt_sigma_deg (the
//     well-posedness test of short_window_map.h: its precision grows with the window's span);
//   A (deferred) otherwise, with the reason.
// The paper's D (SfM-based visual-inertial alignment, chosen on angular excitation with enough tracked
// features) needs visual factors, which this estimator does not have yet: it is never chosen.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <string_view>

#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

enum class InitMode { kStatic, kLidarAided, kDeferred };  // the paper's S, M, A

char InitModeLetter(InitMode mode);            // 'S', 'M', 'A'
std::string_view InitModeName(InitMode mode);  // "static", "lidar-aided", "deferred"

struct InitIndicators {
  int imu_samples = 0;
  double imu_span_s = 0;  // from the first to the last sample
  Eigen::Vector3d mean_acc = Eigen::Vector3d::Zero(), mean_gyro = Eigen::Vector3d::Zero();
  double gyro_std = 0;        // E_omega, rad/s
  double acc_std = 0;         // m/s^2
  double acc_norm_error = 0;  // ||mean acc| - gravity|, m/s^2
  // The largest |integral of (rate - mean rate)| and |integral of (specific force - mean)| over the window:
  // how far vibration, or a motion, turns the body and changes its velocity, rad and m/s.
  double angle_excursion_rad = 0, velocity_excursion_mps = 0;
  double lo_speed = 0;        // E_v, m/s (0 with fewer than two poses)
  double lo_raw_speed = 0;    // |v| of the line, without the noise allowance, m/s
  int scans = 0;              // in the window
  int lidar_scans = 0;        // N_lidar: those registered (M uses them)
};

// The IMU indicators over `samples` and E_v over `poses` (T_lo_imu at `stamps`; the scans' middles in LIO,
// the nodes in WIO) with their position noise `position_sigma_m`; the scan counts are the caller's.
InitIndicators ComputeInitIndicators(std::span<const ImuSample> samples, std::span<const Stamp> stamps,
                                     std::span<const SE3> poses, double position_sigma_m, double gravity);

// Why the window is not at rest by S's limits (the first limit exceeded), or "" when it is.
std::string NotStaticReason(const InitIndicators& indicators, const InertialInitConfig& config,
                            double gravity);

struct ModeDecision {
  InitMode mode = InitMode::kDeferred;
  std::string reason;  // why this mode (A: what is missing)
};

ModeDecision SelectInitMode(const InitIndicators& indicators, const InertialInitConfig& config,
                            double gravity);

}  // namespace uf::estimator
