#include "odometry/sim/trajectory_spline.h"

#include <array>
#include <cassert>
#include <utility>

#include "odometry/sim/cumulative_spline.h"

namespace uf {

TrajectorySpline::TrajectorySpline(Stamp begin, Stamp knot_spacing, std::vector<SE3> control_points)
    : begin_(begin), knot_spacing_(knot_spacing), control_points_(std::move(control_points)) {}

TrajectorySpline TrajectorySpline::FromControlPoints(Stamp begin, Stamp knot_spacing,
                                                     std::vector<SE3> control_points) {
  assert(knot_spacing > 0 && control_points.size() >= 4);
  return TrajectorySpline(begin, knot_spacing, std::move(control_points));
}

TrajectorySpline::State TrajectorySpline::Evaluate(Stamp t) const {
  assert(Contains(t));
  const spline::SegmentCoordinate where = spline::LocateSegment(t, begin_, knot_spacing_, segments());
  std::array<Eigen::Vector3d, 4> positions;
  std::array<SO3, 4> rotations;
  for (int i = 0; i < 4; ++i) {
    positions[i] = control_points_[where.index + i].translation();
    rotations[i] = control_points_[where.index + i].so3();
  }
  const double spacing_seconds = ToSeconds(knot_spacing_);
  const spline::PositionSegmentState position =
      spline::EvaluatePositionSegment(positions, where.u, spacing_seconds);
  const spline::RotationSegmentState rotation =
      spline::EvaluateRotationSegment(rotations, where.u, spacing_seconds);
  State state;
  state.T_world_body = SE3(rotation.rotation, position.position);
  state.velocity_world = position.velocity;
  state.acceleration_world = position.acceleration;
  state.angular_velocity_body = rotation.angular_velocity;
  state.angular_acceleration_body = rotation.angular_acceleration;
  return state;
}

SE3 TrajectorySpline::Pose(Stamp t) const {
  // p(u) = c_0 + sum_{j=1..3} lambda_j(u) (c_j - c_{j-1}),
  // R(u) = R_0 prod_{j=1..3} Exp(lambda_j(u) Log(R_{j-1}^T R_j))   (cumulative_spline.h)
  assert(Contains(t));
  const spline::SegmentCoordinate where = spline::LocateSegment(t, begin_, knot_spacing_, segments());
  const Eigen::Vector4d lambda = spline::CumulativeBasisAt(where.u).value;
  Eigen::Vector3d position = control_points_[where.index].translation();
  SO3 rotation = control_points_[where.index].so3();
  for (int j = 1; j < 4; ++j) {
    const SE3& previous = control_points_[where.index + j - 1];
    const SE3& current = control_points_[where.index + j];
    position += lambda(j) * (current.translation() - previous.translation());
    rotation = rotation * SO3::Exp(lambda(j) * (previous.so3().inverse() * current.so3()).Log());
  }
  return SE3(rotation, position);
}

}  // namespace uf
