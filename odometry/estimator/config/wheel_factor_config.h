// Configuration of the wheel odometry preintegration and factor (preintegration/wheel_preintegration.h,
// factors/wheel_factor.h): the noise model of the wheel twist, the gaps and time offset of the wheel stream,
// and the wheel scale. The extrinsic T_imu_wheel is not here: it comes from the calibration (the wheel
// stream's T_body_sensor), like every extrinsic.
//
// Densities are continuous-time white noise on the twist (as the IMU's, imu_noise_params.h): over a step of
// dt seconds a density sigma becomes a variance sigma^2 / dt, so over an interval of T seconds the integrated
// error has the standard deviation sigma sqrt(T) (m for the velocities, rad for the rates).
//
// Non-holonomic model: a ground vehicle's base frame (x forward, y left, z up) moves along its x axis and
// turns about its z axis; its lateral and vertical velocity and its roll and pitch rates are close to zero
// but not zero (tyre side slip, suspension, a mount away from the rear axle, bumps). Readers of
// nav_msgs/Odometry deliver the full twist, and the simulator (sim/wheel_model.h) (v_x, 0, 0) and (0, 0,
// w_z): either way those four components are taken as measured with the soft densities below, so that only
// the forward distance and the yaw are constrained firmly.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

// Correlation time of the body's oscillation on its suspension: 1 / (2 pi f) with f ~ 1 Hz, the body
// bounce and pitch frequency of road vehicles (1-1.5 Hz).
inline constexpr double kSuspensionTiltTime_s = 0.16;
// How long a lean or squat lasts: the accelerations that tilt a body (pulling away, a turn, braking) last a
// second or more; shorter ones the suspension (~1 Hz) does not follow.
inline constexpr double kTiltManoeuvreTime_s = 1.0;

// Reliability scheduling of the wheel (docs/METHOD.md "Factor-wise reliability scheduling";
// schedule/wheel_consistency.h, schedule/activation_gate.h): each node interval's wheel motion is scored
// against the IMU's prediction of it before its factor joins the window, and the factor is left out while
// the gate is shut. Only where the IMU predicted the node (LIO and WIO windows, not the LO fallback).
struct WheelScheduleConfig {
  bool enabled = true;
  // D = speed_weight min(1, e_v / speed_tolerance_mps) + (1 - speed_weight) min(1, e_psi / ...). A 30 %
  // slip at 8 m/s disagrees by 2.4 m/s; the noise of a 0.1 s interval (wheel speed, the predicted
  // velocity) is a few cm/s, of the yaw rate up to 0.15 rad/s with a noisy encoder.
  double speed_tolerance_mps = 0.5;
  double yaw_rate_tolerance_rad_s = 1.0;  // the wheel's yaw is noisier than its speed, the gyro's is not
  double speed_weight = 0.5;
  // While the wheel is out, the IMU alone carries the speed (in WIO) and its prediction drifts: the speed
  // tolerance grows by this per second since the gate shut, so that the wheel is admitted again once the
  // slip ends instead of being held out by the drift (simulated urban WIO: the predicted speed was 0.1-0.3
  // m/s off 1-3 s after a 7 s slip). A slip that lasts far longer is admitted again when the tolerance
  // has grown to several times its disagreement.
  double drift_mps_per_s = 0.1;
  // After this long shut the wheel is admitted again whatever its score, and its current disagreement
  // becomes the baseline (u_0): by then the IMU's own prediction is not a reference to hold it out by. A
  // slow wheel fault the baseline followed (wheels off the ground while the vehicle speeds up: the frozen
  // reading drifts from the truth by a few cm/s per interval) shuts the gate when it ends, and the state,
  // which followed the wheel, may never agree with it again; this bounds that (and a slip longer than this
  // is taken back, as without scheduling).
  double max_shut_s = 10.0;
  // The speed disagreement of the admitted intervals, averaged over about this long, is what the window's
  // own velocity error accounts for (u_0 in schedule/wheel_consistency.h); 0 compares with the IMU as is.
  // Short, because that error can change fast: in the simulated LiDAR-degenerate corridor the window's
  // velocity lags the pull-away by up to 0.7 m/s, growing ~1 m/s per second; averaged over 1 s the
  // wheel was left out on clean data (LWIO ATE 0.135 -> 0.261 m), over 0.3 s never. A slip's onset is a
  // step the average does not follow (it only takes admitted intervals).
  double baseline_time_s = 0.3;
  // A wheel fault that builds up slowly is followed by u_0 and by the window's velocity: wheels off the
  // ground report their last speed while the vehicle speeds up, and the state, the IMU's biases with it,
  // follows the frozen reading a few cm/s per interval (simulated urban WIO, 4 s off the ground while
  // accelerating: ATE 4.2 m against 0.95 m without scheduling). The wheel's speed change over the last
  // change_window_s against the IMU's (sum over the intervals of (v_wheel(to) - v_wheel(from)) -
  // (v_imu(to) - v_imu(from)), which does not depend on the window's velocity) catches it; e_v is the larger
  // of the two disagreements. 0 turns it off. It is also how long the wheel joins unscored after the
  // inertial initialization and after a clipped IMU interval, where the IMU's prediction is not yet to be
  // trusted (WheelProvider::Link).
  double change_window_s = 1.0;
  // tau_c: the disagreement of the speed changes that saturates the speed term (alone it shuts the gate at
  // half of it). Measured (simulated, 60 s): at 0.5 m/s, as tau_v, the end of a pull-away shut it on clean
  // data (urban WIO +6 %, corridor LWIO +25 %); at 0.75 and 1.0 never; a pull-away with the wheels off the
  // ground is still caught within 0.2 s.
  double change_tolerance_mps = 1.0;
  // Shut at D > threshold (0.25: a speed disagreement of half its tolerance alone), open again after
  // release_keyframes intervals at D <= threshold - release_margin.
  double threshold = 0.25;
  double release_margin = 0.1;
  int release_keyframes = 3;
};

struct WheelFactorConfig {
  // Forward speed (v_x). Encoder counts integrate without drift, so this covers what they do not see: tyre
  // deformation, uneven ground and small slip. 0.05 gives 5 cm over 1 s, ~0.6 % of the distance at 8 m/s;
  // the slow error of the wheel radius is the scale's, not this noise's.
  double forward_velocity_density = 0.05;  // m/s/sqrt(Hz)
  // Yaw rate (w_z). A differential drive's yaw depends on the effective baseline, which the tyres' contact
  // patches and any skid change: less precise than the forward speed. 0.01 gives 0.6 degrees over 1 s (a
  // MEMS gyro is ~10x better, so with an IMU the yaw comes mostly from the IMU).
  double yaw_rate_density = 0.01;  // rad/s/sqrt(Hz)
  // Lateral and vertical velocity (v_y, v_z), soft non-holonomic constraint. The base frame is rigid to the
  // body (T_imu_wheel), but the body rolls and pitches on its suspension against the road the wheels roll
  // on, so the base's velocity leaves its x axis by the tilt angle theta: v_y, v_z ~ v theta. That part
  // grows with the speed v and is modelled below (suspension_tilt_sigma, tilt_per_acceleration); this
  // density is what is left at any speed: tyre deformation, a base a few centimetres off the axle's
  // no-slip point. 0.02 gives 2 cm over 1 s. Skid-steer vehicles turning in place slide sideways and need
  // more (their instantaneous centre of rotation moves off the axle).
  double nonholonomic_velocity_density = 0.02;  // m/s/sqrt(Hz)
  // The body's tilt on its suspension, theta = theta_osc + k a (roll for v_y, pitch for v_z):
  // - theta_osc oscillates about the rest attitude: RMS suspension_tilt_sigma, correlated over
  //   kSuspensionTiltTime_s. 0.01 rad (0.6 degrees) is a passenger car's body motion on an ordinary road;
  //   rough terrain gives several times that (the simulator's wild scene: ~0.04 rad).
  // - k a is the lean in turns (a = v w_z, the lateral acceleration; roll) and the squat and dive under the
  //   longitudinal acceleration a = dv/dt (pitch), k = tilt_per_acceleration, held over
  //   kTiltManoeuvreTime_s. 0.01 rad per m/s^2 (5.6 degrees per g) is a passenger car's roll gradient
  //   (4-7 degrees per g); its pitch gradient is smaller, so this bounds both.
  // Each is a first-order Gauss-Markov process (variance sigma^2, correlation time tau), whose spectral
  // density at low frequency is 2 sigma^2 tau: over intervals longer than tau it acts as white noise of
  // that density, and over shorter ones it overstates the variance (safe). With the speed v and the
  // acceleration a of each step:
  //   density_y^2 = nonholonomic_velocity_density^2 + 2 v^2 (tau_osc sigma^2 + tau_man (k a_lat)^2)
  //   density_z^2 = nonholonomic_velocity_density^2 + 2 v^2 (tau_osc sigma^2 + tau_man (k a_long)^2)
  // At 8 m/s cruising straight: 0.05 m/s/sqrt(Hz). Zero switches a term off.
  double suspension_tilt_sigma = 0.01;  // rad
  double tilt_per_acceleration = 0.01;  // rad per m/s^2
  // Roll and pitch rates (w_x, w_y), soft: 0.1 = 10x the yaw density, 5.7 degrees over 1 s; body roll in
  // turns and pitch over bumps and grades are real, and the IMU observes them far better.
  double roll_pitch_rate_density = 0.1;  // rad/s/sqrt(Hz)

  // A step between consecutive wheel samples longer than this inside an interval (the samples that bracket
  // its ends included) is a gap: the preintegration fails rather than interpolate linearly across it. 0.2 s
  // is two periods of a 10 Hz odometry (one dropped message), or nine dropped samples at 50 Hz.
  double max_gap_s = 0.2;  // s
  // Added to the wheel stamps to put them on the estimator's clock: t = stamp + time_offset_s. Fixed (not
  // estimated); 0 when the dataset's per-stream offset (dataset.time_offsets_s) already aligns the streams.
  double time_offset_s = 0.0;  // s, |.| <= 1

  // The wheel scale s multiplies the reported linear velocity (wrong wheel radius, tyre pressure, load).
  // Estimated by default, as one parameter block shared by the wheel factors; with false the caller holds
  // the block constant at 1. The LIO window frees it only in the solves where the LiDAR observes it
  // (WheelScaleObservable, lidar_odometry/window_solve.cpp) and holds it at its current value otherwise.
  bool estimate_scale = true;
  // The scale block's prior, (s - 1) / scale_prior_sigma (relative): 0.05 allows the few percent a tyre's
  // rolling radius differs from its nominal value, and keeps s near 1 while the motion does not observe it
  // (standing still).
  double scale_prior_sigma = 0.05;
  // The stationary branch (a zero-velocity update): where every wheel sample over a node interval reads
  // no motion, the interval's nodes are held at one pose with zero velocity (factors/zero_motion_factor.h).
  // At rest a LiDAR's registration still wanders (by centimetres along a corridor), and the window would
  // otherwise explain that with velocity and accelerometer bias. Wheels that stand while the vehicle moves
  // (towed, on a ferry) need false. Off here and in WIO, on in the LIO window (lidar_odometry_config.h):
  // in WIO it made the wheel scale worse (docs/METHOD.md "Stationary branch").
  bool stationary_updates = false;

  WheelScheduleConfig schedule;

  // Ok, or the first bad field with its value ("lio.wheel.<field>: must be ..., got ...").
  Status Validate() const;
};

}  // namespace uf::estimator
