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

}  // namespace uf
