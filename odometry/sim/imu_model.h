// Simulated IMU on a TrajectorySpline: exact specific force and angular rate of an IMU mounted at T_body_imu,
// plus white noise, bias random walk and saturation from datasheet-style continuous-time densities.
//
// True signals, for a z-up world with gravity g_world = (0, 0, -gravity):
//   p_imu = p_body + R_world_body r,  r = translation of T_body_imu (the lever arm, body frame)
//   a_imu = a_body + R_world_body (alpha x r + omega x (omega x r))   (omega, alpha: body frame)
//   acc   = R_world_imu^T (a_imu - g_world)   (specific force: +gravity along the imu's up axis at rest)
//   gyro  = omega_imu = R_body_imu^T omega
// Measured: acc + b_a + n_a and gyro + b_g + n_g, each axis clamped to +-saturation when saturation > 0.
//
// Discretisation, the Kalibr / EuRoC convention (Kalibr wiki, "IMU Noise Model"): at rate f = 1/dt a
// white-noise density sigma (unit/sqrt(Hz)) gives per-sample standard deviation sigma * sqrt(f), and a bias
// random walk density sigma_b (unit/s/sqrt(Hz)) gives per-step increments of standard deviation
// sigma_b * sqrt(dt), so the bias variance grows as sigma_b^2 * t.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf {

constexpr double kStandardGravity = 9.80665;  // m/s^2

// All zero by default: a noise-free, bias-free, unsaturated IMU.
struct ImuNoise {
  double accel_noise_density = 0.0;                              // m/s^2/sqrt(Hz)
  double gyro_noise_density = 0.0;                               // rad/s/sqrt(Hz)
  double accel_bias_random_walk = 0.0;                           // m/s^3/sqrt(Hz)
  double gyro_bias_random_walk = 0.0;                            // rad/s^2/sqrt(Hz)
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();  // m/s^2, imu frame, at the first sample
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();   // rad/s, imu frame, at the first sample
  double accel_saturation = 0.0;                                 // m/s^2 per axis; 0 = no saturation
  double gyro_saturation = 0.0;                                  // rad/s per axis; 0 = no saturation
};

// The true motion of the imu frame at one instant.
struct ImuKinematics {
  SE3 T_world_imu;
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();        // of the imu origin, m/s
  Eigen::Vector3d acceleration_world = Eigen::Vector3d::Zero();    // of the imu origin, m/s^2
  Eigen::Vector3d angular_velocity_imu = Eigen::Vector3d::Zero();  // rad/s, imu frame
};

struct ImuBiases {
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2, imu frame
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s, imu frame
};

struct SimulatedImu {
  std::vector<ImuSample> samples;  // what the sensor reports
  std::vector<ImuBiases> biases;   // the true bias in each sample (ground truth), one per sample
};

class ImuSimulator {
 public:
  // Fails, naming the value, for a rate that is not in (0, 1e9] Hz, a negative or non-finite density or
  // saturation, a non-finite initial bias or extrinsic, or a gravity that is not finite and >= 0.
  static Expected<ImuSimulator> Create(TrajectorySpline trajectory, const SE3& T_body_imu, double rate_hz,
                                       const ImuNoise& noise, std::uint64_t seed,
                                       double gravity = kStandardGravity);

  // The true imu motion at t; asserts that the trajectory covers t.
  ImuKinematics Kinematics(Stamp t) const;
  // The noise-free, bias-free, unsaturated measurement at t; asserts that the trajectory covers t.
  ImuSample IdealSample(Stamp t) const;

  // Samples at begin + round(k * 1e9 / rate_hz) ns up to end. Each call starts again from the seed and the
  // initial biases, so the output depends only on the arguments (the same seed gives the same samples on
  // every platform). Fails when [begin, end] is empty or not inside the trajectory.
  Expected<SimulatedImu> Generate(Stamp begin, Stamp end) const;

  const TrajectorySpline& trajectory() const { return trajectory_; }
  const SE3& T_body_imu() const { return T_body_imu_; }
  double rate_hz() const { return rate_hz_; }

 private:
  ImuSimulator(TrajectorySpline trajectory, const SE3& T_body_imu, double rate_hz, const ImuNoise& noise,
               std::uint64_t seed, double gravity);

  TrajectorySpline trajectory_;
  SE3 T_body_imu_;
  double rate_hz_;
  ImuNoise noise_;
  std::uint64_t seed_;
  double gravity_;
};

}  // namespace uf
