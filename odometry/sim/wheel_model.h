// Simulated wheel odometry of a differential-drive vehicle on a TrajectorySpline: the forward speed and yaw
// rate that the vehicle computes from its two wheel encoders, with calibration errors of the wheel radius
// and the baseline, encoder quantisation, wheel-speed noise, wheel slip and wheels off the ground.
//
// Frames: the wheel frame (vehicle base: x forward, y left, z up, origin midway between the wheels) sits at
// T_body_wheel; r = translation of T_body_wheel is the lever arm in the body frame. Its true motion, with
// v_body, omega (body frame) from the spline:
//   v_wheel = R_world_wheel^T (v_world_body + R_world_body (omega x r))
//   w_wheel = R_body_wheel^T omega,   with R_world_wheel = R_world_body R_body_wheel
// Differential drive, true radius r_w and baseline b (distance between the wheel contact points):
//   ground speed of each wheel  v_l = v_x - w_z b / 2,  v_r = v_x + w_z b / 2
//   wheel angular rate          phi_dot_l = (1 + s) v_l / r_w,  phi_dot_r = (1 + s) v_r / r_w   (s: slip)
// The odometry inverts this with its calibrated r' = r_w (1 + radius_error), b' = b (1 + baseline_error):
//   v_x = r' (phi_dot_r + phi_dot_l) / 2,  w_z = r' (phi_dot_r - phi_dot_l) / b'
// so a radius error scales v_x and w_z by (1 + radius_error), a baseline error scales w_z by
// 1 / (1 + baseline_error), and a slip s scales both by (1 + s).
// Non-holonomic assumption: the odometry reports only v_x and w_z (WheelSample: linear (v_x, 0, 0), angular
// (0, 0, w_z)); the true lateral and vertical velocity and the roll and pitch rates (in WheelTruth) are not
// measured, and are not zero when the mount is offset or tilted or the vehicle skids.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "odometry/sim/time_window.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::sim {

// Defaults: an ideal encoder (no error, noise or quantisation) on a 0.165 m wheel, 0.555 m baseline.
struct WheelConfig {
  double rate_hz = 50.0;          // samples per second, in (0, 10000]
  double wheel_radius_m = 0.165;  // true wheel radius r_w, > 0
  double baseline_m = 0.555;      // true distance between the wheels b, > 0
  double radius_error = 0.0;      // relative, > -1: the odometry computes with r' = r_w (1 + radius_error)
  double baseline_error = 0.0;    // relative, > -1: the odometry computes with b' = b (1 + baseline_error)
  // Encoder ticks per wheel revolution, >= 0; 0 = continuous. Quantised, the encoder reports the whole
  // ticks counted since the previous sample divided by the sample interval: the mean rate over the interval,
  // to within one tick per interval (the true wheel angle is integrated by the trapezoid rule between
  // samples; each wheel's encoder starts at a random fraction of a tick drawn from the seed).
  double encoder_resolution_ticks = 0.0;
  // Gaussian white noise sigma (rad/s, >= 0) added to each wheel's reported rate in each sample, after the
  // quantisation (jitter, tyre deformation): v_x gets std r' sigma / sqrt(2), w_z sqrt(2) r' sigma / b'.
  double wheel_speed_noise_std = 0.0;
  // Window -> slip ratio s (finite, >= -1): inside, both wheels turn (1 + s) times faster than their ground
  // speed (s = -1: locked wheels). Where windows overlap, their factors multiply.
  std::vector<std::pair<TimeWindow, double>> slips;
  // Wheels off the ground: inside a window both wheels keep turning at the rates of the last sample before
  // the window (the sample grid extended backwards if the window starts before the first sample, clamped to
  // the start of the trajectory), slip included, frozen until the window ends; quantisation and noise go on
  // as usual. Where windows overlap, the first listed that contains the sample decides.
  std::vector<TimeWindow> floats;

  // Fails naming the field and value, e.g. "wheel.rate_hz: must be in (0, 10000], got -5".
  Status Validate() const;
};

// The true motion of the wheel frame at one sample (see the header comment).
struct WheelTruth {
  Stamp stamp = 0;
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   // m/s, wheel frame (all three components)
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s, wheel frame
};

struct SimulatedWheel {
  std::vector<WheelSample> samples;  // what the odometry reports
  std::vector<WheelTruth> truth;     // the true wheel-frame motion, one per sample
};

class WheelSimulator {
 public:
  // Fails for an invalid config (see WheelConfig::Validate) or a non-finite T_body_wheel.
  static Expected<WheelSimulator> Create(TrajectorySpline trajectory, const SE3& T_body_wheel,
                                         const WheelConfig& config, std::uint64_t seed);

  // The true wheel-frame motion at t; asserts that the trajectory covers t.
  WheelTruth TrueMotion(Stamp t) const;

  // Samples at begin + round(k * 1e9 / rate_hz) ns up to end. Each call starts again from the seed, so the
  // output depends only on the arguments. Fails when [begin, end] is empty or not inside the trajectory.
  Expected<SimulatedWheel> Generate(Stamp begin, Stamp end) const;

  const TrajectorySpline& trajectory() const { return trajectory_; }
  const SE3& T_body_wheel() const { return T_body_wheel_; }
  const WheelConfig& config() const { return config_; }

 private:
  WheelSimulator(TrajectorySpline trajectory, const SE3& T_body_wheel, const WheelConfig& config,
                 std::uint64_t seed);

  // True (left, right) wheel rates at t in rad/s, slip included, float not.
  Eigen::Vector2d WheelRates(Stamp t) const;

  TrajectorySpline trajectory_;
  SE3 T_body_wheel_;
  WheelConfig config_;
  std::uint64_t seed_;
};

}  // namespace uf::sim
