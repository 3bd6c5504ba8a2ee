// Configuration of the inertial initialization of LIO (init/inertial_initializer.h and the parts it uses:
// init_mode_selection.h, inertial_alignment.h, short_window_map.h, init_admission.h): the thresholds of the
// mode selection (static S, LiDAR-aided M, deferred A), of the modes and of the admission check. The WIO
// window uses the static and gravity-norm keys only (its moving mode is the wheel-aided linear alignment).
//
// Why the defaults (docs/METHOD.md "Observability-aware initialization" has the measurements):
// - static_max_gyro_std 0.02 rad/s, static_max_acc_std 0.3 m/s^2 (as before this initialization): at rest the
//   spread of a sample is its white noise times sqrt(rate), 0.004 rad/s and 0.05 m/s^2 (3D RMS) for the
//   simulated ADIS16448 at 200 Hz; a start moves more: a car pulling away at 1 m/s^2, a robot turning at
//   0.1 rad/s.
// - static_max_vibration_deg 0.25: a platform whose motors run at rest (EuRoC's MAV: spread 0.08 rad/s and
//   1.1 m/s^2, far above the two limits above) turns its body by 0.16 deg at most over 2 s and gains 0.04 m/s
//   at most; a start turns and gains far more. 0.25 deg of turning tilts the mean specific force by less.
// - static_min_duration_s 0.1: 20 samples at 200 Hz give the gyro bias to 0.0024 / sqrt(20) = 5e-4 rad/s and
//   the gravity direction to 0.028 / sqrt(20) / 9.81 = 0.04 deg (the paper's static gravity uses 1.0 s).
// - static_max_speed_mps 0.05: S sets v = 0, so the LO speed it tolerates beyond 3 sigma of the LO noise is
//   the velocity error it admits (the target is 0.05 m/s); with two scans that noise allowance is another
//   0.085 m/s at lidar_position_sigma_m. Over WIO's 1 s window it is the former static_max_motion_m, 0.05 m.
// - lidar_position_sigma_m 0.002: the least noise of an LO scan position (its middle): at rest the middles of
//   the first scans scatter by 2-4 mm in the simulated streets and warehouse (16 or 32 beams), 1-4 cm on the
//   rough wild terrain; M uses the larger of this and the noise its residuals show.
// - max_tilt_sigma_deg 0.25: M's gravity direction within 0.5 deg at 2 sigma. The accelerometer bias prior
//   alone leaves accel_bias_sigma / gravity = 0.12 deg without rotation, so the LO part must come below
//   0.2 deg: the window's span grows until it does (the direction comes from the LO positions' second
//   difference: its error falls as the LO noise / span^2).
// - accel_bias_sigma 0.02 m/s^2: a MEMS turn-on bias (as wio.init_accel_bias_sigma).
// - map_settle_scans 2: the map's first sweep is mapped as if at rest until the next scans give its motion
//   (docs/METHOD.md "Sliding window and solve", the first sweep of a map); the two scans registered before
//   that are off by centimetres. On 30 simulated moving starts M's gravity was off by 0.22 deg RMS with 2,
//   0.26 deg with 1 (0.1 s sooner), 1.6 deg worst with 1 before the settling test (CheckGravitySettled).
// - max_scans 20: the paper's LiDAR init frames; 2 s at 10 Hz.
// - max_chi2_per_dof 3: the IMU's velocity changes against the admitted state, whitened by the estimator's
//   IMU noise (10x the simulated IMU's): consistent windows give 0.004-0.3 per dof; a static start with its
//   specific force tilted by 3 deg for 0.15 s 4.8-5.8.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialInitConfig {
  // M needs this many registered scans in its window (the paper's N_min^lidar).
  int min_scans = 3;
  // M leaves out a local map's first scans: its first sweep is mapped as if at rest until the next scans give
  // its motion, so on a moving start the scans registered against it first are off by centimetres.
  int map_settle_scans = 2;
  // The initialization window holds at most this many scans, the older ones after they left the odometry
  // window (the paper initializes over 20 LiDAR frames).
  int max_scans = 20;
  // S: the IMU at rest for at least this long, its spread under these limits, the LO (or wheel) slower
  // (init_mode_selection.h).
  double static_min_duration_s = 0.1;  // s
  double static_max_gyro_std = 0.02;   // rad/s: spread of the angular rate (RMS of the 3D deviation)
  double static_max_acc_std = 0.3;     // m/s^2: spread of the specific force
  double static_max_speed_mps = 0.05;  // m/s: E_v, the LO (WIO: wheel) speed beyond 3 sigma of its noise
  // A spread above its limit is still rest when it is vibration: the angle the body turns (its angular rate
  // less the mean, integrated) stays within this and the velocity it gains (the specific force less the
  // mean, integrated) within static_max_speed_mps (init_mode_selection.h).
  double static_max_vibration_deg = 0.25;  // deg
  // S and M: admitted when ||g| - gravity| <= this fraction of gravity (S: the mean specific force).
  double max_gravity_error = 0.1;
  // M (LIO): admitted once the predicted standard deviation of the gravity direction is this small.
  double max_tilt_sigma_deg = 0.25;       // deg
  double lidar_position_sigma_m = 0.002;  // m: least noise of an LO scan position (E_v and M)
  double accel_bias_sigma = 0.02;         // m/s^2: M's prior on the accelerometer bias (about 0)
  // Admission check (LIO, init_admission.h): the IMU's velocity changes against the admitted state,
  // whitened, chi-square per degree of freedom.
  double max_chi2_per_dof = 3.0;

  Status Validate() const;  // names the field and value ("lio.init.<field>: ...")
};

}  // namespace uf::estimator
