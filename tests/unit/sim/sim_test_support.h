// Helpers of the simulator tests: a smooth analytic motion (a vehicle-like drive with turns through more than
// pi of yaw, rolling and pitching), splines from random control points, and recording measured figures.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/trajectory.h"

namespace uf::test {

// T_world_body(t) of the smooth motion, t in seconds.
inline SE3 SmoothPose(double t) {
  const Eigen::Vector3d position(4.0 * std::sin(0.4 * t) + 0.5 * t, 3.0 * std::sin(0.3 * t + 0.5),
                                 0.3 * std::sin(0.9 * t));
  const double yaw = 0.6 * t + 0.4 * std::sin(0.7 * t);
  const double pitch = 0.15 * std::sin(0.8 * t + 1.0);
  const double roll = 0.2 * std::sin(1.1 * t);
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return SE3(SO3(R), position);
}

// Its velocity, d/dt of the position above.
inline Eigen::Vector3d SmoothVelocity(double t) {
  return Eigen::Vector3d(1.6 * std::cos(0.4 * t) + 0.5, 0.9 * std::cos(0.3 * t + 0.5),
                         0.27 * std::cos(0.9 * t));
}

// The smooth motion sampled at rate_hz from `start` for duration_s seconds.
inline Trajectory SampleSmoothTrajectory(Stamp start, double duration_s, double rate_hz) {
  Trajectory trajectory;
  const int count = static_cast<int>(std::lround(duration_s * rate_hz)) + 1;
  for (int i = 0; i < count; ++i) {
    const Stamp offset = FromSeconds(i / rate_hz);
    trajectory.stamps.push_back(start + offset);
    trajectory.poses.push_back(SmoothPose(ToSeconds(offset)));
  }
  return trajectory;
}

// A spline through `count` random control points: positions a random walk of `position_step` m per knot,
// rotations one of `rotation_step` rad per knot, so the motion is brisk and turns about every axis.
inline TrajectorySpline RandomSpline(unsigned seed, int count, Stamp knot_spacing, double position_step = 0.3,
                                     double rotation_step = 0.25) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto draw = [&] {  // one statement per draw: argument evaluation order differs between compilers
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v(i) = uniform(engine);
    return v;
  };
  std::vector<SE3> control;
  Eigen::Vector3d position = draw();
  SO3 rotation = SO3::Exp(draw());
  for (int i = 0; i < count; ++i) {
    control.emplace_back(rotation, position);
    position += position_step * draw();
    rotation = rotation * SO3::Exp(rotation_step * draw());
  }
  return TrajectorySpline::FromControlPoints(1'000'000'000, knot_spacing, control);
}

// Records a measured figure in the test's XML report (--gtest_output=xml), with all its digits.
inline void RecordFigure(const std::string& key, double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  ::testing::Test::RecordProperty(key, text.str());
}

}  // namespace uf::test
