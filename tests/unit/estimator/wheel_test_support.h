// What the wheel preintegration and wheel factor tests share: the simulator's default trajectories and wheel
// mounts, the true twist as samples, and the preintegrated motion's error against the spline with the bound
// the integration rules give.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <utility>
#include <vector>

#include "odometry/estimator/preintegration/wheel_preintegration.h"
#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/sim/wheel_model.h"
#include "odometry/types/se3.h"

namespace uf::estimator::testing {

inline constexpr Stamp kSecond = kNanosecondsPerSecond;
inline constexpr Stamp kMillisecond = kSecond / 1000;

// A scene's default trajectory (12 s; standing for the first second, cruising from ~3 s) as the simulator
// fits it: a spline with knots every 0.1 s.
inline TrajectorySpline DefaultTrajectory(const char* scene) {
  auto poses = sim::DefaultSceneTrajectory(scene, 12.0, 3, 0);
  EXPECT_TRUE(poses.ok()) << poses.error();
  auto spline = TrajectorySpline::FitPoses(*poses, kSecond / 10);
  EXPECT_TRUE(spline.ok()) << spline.error();
  return std::move(spline).value();
}

// Wheel mounts on the body (= the imu in the simulator): a level base frame at the rear axle, behind and
// below the imu, and a tilted, offset one that gives every component of the twist.
inline const SE3 kRearAxle(SO3(), Eigen::Vector3d(-0.3, 0.0, -0.25));
inline const SE3 kTilted(SO3::Exp(Eigen::Vector3d(0.03, -0.05, 0.2)), Eigen::Vector3d(-0.6, 0.2, -0.4));

inline sim::WheelSimulator Wheel(const char* scene, const SE3& T_body_wheel, double rate_hz,
                                 const sim::WheelConfig& base = {}) {
  sim::WheelConfig config = base;
  config.rate_hz = rate_hz;
  auto wheel = sim::WheelSimulator::Create(DefaultTrajectory(scene), T_body_wheel, config, 1);
  EXPECT_TRUE(wheel.ok()) << wheel.error();
  return std::move(wheel).value();
}

inline sim::SimulatedWheel Generate(const sim::WheelSimulator& wheel, Stamp begin, Stamp end) {
  auto generated = wheel.Generate(begin, end);
  EXPECT_TRUE(generated.ok()) << generated.error();
  return std::move(generated).value();
}

// The true twist as samples: all six components, what a reader of nav_msgs/Odometry could deliver.
inline std::vector<WheelSample> TruthSamples(const sim::SimulatedWheel& simulated) {
  std::vector<WheelSample> samples;
  for (const sim::WheelTruth& truth : simulated.truth)
    samples.push_back({truth.stamp, truth.linear_velocity, truth.angular_velocity});
  return samples;
}

inline SE3 WheelPose(const sim::WheelSimulator& wheel, Stamp t) {
  return wheel.trajectory().Pose(t) * wheel.T_body_wheel();
}

inline WheelPreintegration Preintegrate(const std::vector<WheelSample>& samples, Stamp from, Stamp to,
                                        const WheelFactorConfig& config = {}) {
  auto pre = WheelPreintegration::Between(samples, from, to, config);
  EXPECT_TRUE(pre.ok()) << pre.error();
  return std::move(pre).value();
}

struct MotionErrors {
  double rotation, position;  // rad, m
};

// The preintegrated motion against T_world_wheel(from)^-1 T_world_wheel(to) from the spline.
inline MotionErrors ErrorsAgainstSpline(const sim::WheelSimulator& wheel, const WheelPreintegration& pre) {
  const SE3 truth = WheelPose(wheel, pre.from()).inverse() * WheelPose(wheel, pre.to());
  return {(truth.so3().inverse() * pre.delta_R()).Log().norm(), (truth.translation() - pre.delta_p()).norm()};
}

// The leading error term of the integration rules over [from, to] at step dt, from the true motion sampled
// every millisecond (second derivatives by central differences):
//   rotation: the trapezoid rule on w errs by dt^3 / 12 |w''| per step, and the midpoint exponential drops
//     the commutator term dt^3 / 12 |w x w'| of the Magnus expansion: T dt^2 / 12 max(|w''| + |w| |w'|);
//   position: the trapezoid rule on f = R_wheel(from)^T R_wheel(t) v(t) errs by T dt^2 / 12 max |f''|, and
//     the rotation error above turns each increment: at most that angle times the path length.
inline MotionErrors ErrorBound(const sim::WheelSimulator& wheel, Stamp from, Stamp to, double dt) {
  const Eigen::Matrix3d R_from_T = WheelPose(wheel, from).rotation().transpose();
  const auto w = [&](Stamp t) { return wheel.TrueMotion(t).angular_velocity; };
  const auto f = [&](Stamp t) {
    return Eigen::Vector3d(R_from_T * WheelPose(wheel, t).rotation() * wheel.TrueMotion(t).linear_velocity);
  };
  const double h = ToSeconds(kMillisecond);
  double max_rotation_term = 0, max_f2 = 0, path = 0;
  for (Stamp t = from; t <= to; t += kMillisecond) {
    const Eigen::Vector3d w1 = (w(t + kMillisecond) - w(t - kMillisecond)) / (2 * h);
    const Eigen::Vector3d w2 = (w(t + kMillisecond) - 2 * w(t) + w(t - kMillisecond)) / (h * h);
    const Eigen::Vector3d f2 = (f(t + kMillisecond) - 2 * f(t) + f(t - kMillisecond)) / (h * h);
    max_rotation_term = std::max(max_rotation_term, w2.norm() + w(t).norm() * w1.norm());
    max_f2 = std::max(max_f2, f2.norm());
    path += f(t).norm() * h;
  }
  const double T = ToSeconds(to - from), k = T * dt * dt / 12;
  return {k * max_rotation_term, k * max_f2 + k * max_rotation_term * path};
}

}  // namespace uf::estimator::testing
