// Fixtures of the LiDAR tests: a brisk trajectory inside BoxRoomScene (5 m/s, yawing at 3 rad/s, rolling and
// pitching) so that rolling acquisition matters, a lidar mounted off-centre and tilted on the body, and
// helpers on scans.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "odometry/sim/sensors/lidar_model.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/se3.h"
#include "sensor_test_scenes.h"

namespace uf::sim::test {

inline constexpr Stamp kTrajectoryBegin = 1'000'000'000'000;  // an arbitrary non-zero epoch, ns
inline constexpr Stamp kKnotSpacing = 100'000'000;            // 0.1 s

// Control point i of the brisk drive, at time (i - 1) * 0.1 s: from (-4, 11, 0) along +x at 5 m/s.
inline TrajectorySpline BriskSpline(int control_points = 16) {
  std::vector<SE3> controls;
  for (int i = 0; i < control_points; ++i) {
    const double t = (i - 1) * 0.1;
    const Eigen::Vector3d position(-4.0 + 5.0 * t, 11.0 + 0.3 * std::sin(3.0 * t), 0.2 * std::sin(5.0 * t));
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(3.0 * t, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.1 * std::cos(3.0 * t), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.1 * std::sin(4.0 * t), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    controls.emplace_back(SO3(R), position);
  }
  return TrajectorySpline::FromControlPoints(kTrajectoryBegin, kKnotSpacing, controls);
}

// A spline standing still at `position` with identity attitude.
inline TrajectorySpline StaticSpline(const Eigen::Vector3d& position, int control_points = 40) {
  return TrajectorySpline::FromControlPoints(kTrajectoryBegin, kKnotSpacing,
                                             std::vector<SE3>(control_points, SE3(SO3(), position)));
}

inline SE3 MountTBodyLidar() {
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return SE3(SO3(R), Eigen::Vector3d(0.3, -0.1, 0.5));
}

// A noise-free, dropout-free config (fewer columns than the default to keep the tests fast).
inline LidarConfig ExactConfig(const std::string& model = "spinning32") {
  LidarConfig config;
  config.model = model;
  config.horizontal_resolution_deg = 0.4;
  config.range_noise_std_m = 0.0;
  config.max_range_m = 80.0;
  return config;
}

inline Eigen::Vector3d PointOf(const LidarPoint& p) { return Eigen::Vector3d(p.x, p.y, p.z); }

// Bitwise equality of two scans.
inline bool Identical(const LidarScan& a, const LidarScan& b) {
  if (a.stamp != b.stamp || a.end != b.end || a.points.size() != b.points.size()) return false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const LidarPoint& p = a.points[i];
    const LidarPoint& q = b.points[i];
    if (p.x != q.x || p.y != q.y || p.z != q.z || p.intensity != q.intensity || p.ring != q.ring ||
        p.offset_ns != q.offset_ns) {
      return false;
    }
  }
  return true;
}

}  // namespace uf::sim::test
