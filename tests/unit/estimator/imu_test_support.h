// Ground truth for the IMU preintegration and IMU factor tests: a spline trajectory with changing rotation
// and acceleration, the simulator's IMU on it, and the true keyframe states.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/sim/imu_model.h"
#include "odometry/sim/trajectory_spline.h"

namespace uf::estimator::testing {

constexpr Stamp kSecond = kNanosecondsPerSecond;

// The constant biases of the simulated IMU in the tests (m/s^2, rad/s).
inline const Eigen::Vector3d kAccelBias(0.08, -0.05, 0.12);
inline const Eigen::Vector3d kGyroBias(0.004, -0.006, 0.003);

// 12 control points 0.5 s apart (4.5 s of motion): rotations of up to ~0.6 rad about all axes and
// positions a few metres apart, so angular rate and acceleration change all the time.
inline TrajectorySpline MovingTrajectory() {
  std::vector<SE3> control;
  for (int k = 0; k < 12; ++k) {
    const double s = 0.7 * k;
    const Eigen::Vector3d phi(0.4 * std::sin(s), 0.3 * std::cos(1.3 * s), 0.5 * std::sin(0.6 * s + 1.0));
    const Eigen::Vector3d p(1.5 * k, 2.0 * std::sin(0.8 * s), 0.5 * std::cos(1.1 * s));
    control.emplace_back(SO3::Exp(phi), p);
  }
  return TrajectorySpline::FromControlPoints(0, kSecond / 2, control);
}

// The IMU on MovingTrajectory, mounted with a lever arm and a tilt, with the given noise and seed.
inline ImuSimulator MovingImu(double rate_hz, const ImuNoise& noise = ImuNoise(), std::uint64_t seed = 1) {
  const SE3 T_body_imu(SO3::Exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.2, 0.1, -0.05));
  auto imu = ImuSimulator::Create(MovingTrajectory(), T_body_imu, rate_hz, noise, seed);
  EXPECT_TRUE(imu.ok()) << imu.error();
  return std::move(imu).value();
}

inline std::vector<ImuSample> Samples(const ImuSimulator& imu, Stamp begin, Stamp end) {
  auto generated = imu.Generate(begin, end);
  EXPECT_TRUE(generated.ok()) << generated.error();
  return generated.value().samples;
}

// The true state of the imu at t with the given (constant) biases.
inline NavState TrueState(const ImuSimulator& imu, Stamp t, const Eigen::Vector3d& accel_bias = {0, 0, 0},
                          const Eigen::Vector3d& gyro_bias = {0, 0, 0}) {
  const ImuKinematics k = imu.Kinematics(t);
  NavState state;
  state.stamp = t;
  state.T_world_imu = k.T_world_imu;
  state.velocity = k.velocity_world;
  state.accel_bias = accel_bias;
  state.gyro_bias = gyro_bias;
  return state;
}

}  // namespace uf::estimator::testing
