// The simulator's ground-truth motion: a C2-continuous body trajectory T_world_body(t), so that velocity,
// acceleration, angular velocity and angular acceleration (what an IMU senses) exist everywhere and are
// exact.
//
// A uniform cumulative cubic B-spline on SE(3), split into a cubic B-spline of positions in R^3 and a
// cumulative cubic B-spline of rotations on SO(3) (see cumulative_spline.h). Control point i sits at
// begin + (i - 1) * knot_spacing; segment s covers [begin + s * knot_spacing, begin + (s + 1) * knot_spacing]
// and uses control points s .. s + 3, so n control points give n - 3 segments.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

class TrajectorySpline {
 public:
  struct State {
    SE3 T_world_body;
    Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();             // m/s, d/dt of the position
    Eigen::Vector3d acceleration_world = Eigen::Vector3d::Zero();         // m/s^2
    Eigen::Vector3d angular_velocity_body = Eigen::Vector3d::Zero();      // rad/s, R^T dR/dt = Hat(omega)
    Eigen::Vector3d angular_acceleration_body = Eigen::Vector3d::Zero();  // rad/s^2, d/dt of the above
  };

  // Resamples a recorded trajectory (TUM, KITTI with times, EuRoC) into a spline with the given knot
  // spacing that starts at the first stamp and covers the last. Positions: linear least squares on the
  // spline positions at the pose stamps. Rotations: Gauss-Newton on sum |Log(R_pose^T R_spline(t))|^2,
  // started from the poses slerped at the control-point times. Both carry a weak smoothness prior (second
  // differences of the control points, weight 1e-6 against one pose), which only decides control points the
  // poses leave free, e.g. where poses are sparser than knots. The rotation between consecutive poses and
  // between consecutive knots must stay well below pi. Fails for fewer than 4 poses, poses without stamps,
  // stamps not strictly increasing, non-finite poses, or knot_spacing <= 0; the message names the value.
  static Expected<TrajectorySpline> FitPoses(const Trajectory& poses, Stamp knot_spacing);

  // From control points (at least 4) and knot spacing > 0 (ns); asserts both.
  static TrajectorySpline FromControlPoints(Stamp begin, Stamp knot_spacing, std::vector<SE3> control_points);

  Stamp begin() const { return begin_; }
  Stamp end() const { return begin_ + segments() * knot_spacing_; }
  Stamp knot_spacing() const { return knot_spacing_; }
  int segments() const { return static_cast<int>(control_points_.size()) - 3; }
  const std::vector<SE3>& control_points() const { return control_points_; }
  bool Contains(Stamp t) const { return t >= begin() && t <= end(); }

  // The pose and its derivatives at t; asserts begin() <= t <= end().
  State Evaluate(Stamp t) const;

  // The pose T_world_body(t) alone (no derivatives): what sensors that sample poses densely need, e.g. the
  // LiDAR once per firing. Same maths as Evaluate; asserts begin() <= t <= end().
  SE3 Pose(Stamp t) const;

 private:
  TrajectorySpline(Stamp begin, Stamp knot_spacing, std::vector<SE3> control_points);

  Stamp begin_;
  Stamp knot_spacing_;
  std::vector<SE3> control_points_;
};

}  // namespace uf
