// One segment of a uniform cumulative cubic B-spline, in R^3 and on SO(3) (Kim, Kim and Shin, "A general
// construction scheme for unit quaternion curves", SIGGRAPH 1995; Sommer, Usenko, Schubert, Demmel and
// Cremers, "Efficient Derivative Computation for Cumulative B-Splines on Lie Groups", CVPR 2020).
//
// A segment is driven by four consecutive control points x_0..x_3 and a normalised time u in [0, 1]. With the
// cumulative basis lambda_j(u) = sum_{i >= j} B_i(u) of the uniform cubic B-spline weights B_i,
//   position  p(u) = c_0 + sum_{j=1..3} lambda_j(u) (c_j - c_{j-1})
//   rotation  R(u) = R_0 prod_{j=1..3} Exp(lambda_j(u) d_j),  d_j = Log(R_{j-1}^T R_j).
// Both are C2 across segments (the weights are those of a cubic B-spline); the rotation stays on SO(3).
#pragma once

#include <Eigen/Core>
#include <array>

#include "odometry/types/so3.h"
#include "odometry/types/stamp.h"

namespace uf::spline {

// The cumulative basis and its derivatives with respect to u; lambda_0 = 1. In matrix form
// lambda(u) = M [1, u, u^2, u^3]^T with M = 1/6 [[6, 0, 0, 0], [5, 3, -3, 1], [1, 3, 3, -2], [0, 0, 0, 1]].
struct CumulativeBasis {
  Eigen::Vector4d value;   // lambda_j(u)
  Eigen::Vector4d first;   // d lambda_j / du
  Eigen::Vector4d second;  // d^2 lambda_j / du^2
};
CumulativeBasis CumulativeBasisAt(double u);

// The ordinary B-spline weights B_i(u) = lambda_i(u) - lambda_{i+1}(u) (lambda_4 = 0): p(u) = sum B_i c_i.
Eigen::Vector4d PositionWeights(double u);

// The segment holding time t of a spline that starts at `begin` with `segments` segments of length
// `spacing` ns, and u in [0, 1] inside it. t = begin + segments * spacing is the end of the last segment.
struct SegmentCoordinate {
  int index = 0;
  double u = 0.0;
};
SegmentCoordinate LocateSegment(Stamp t, Stamp begin, Stamp spacing, int segments);

struct PositionSegmentState {
  Eigen::Vector3d position, velocity, acceleration;  // per second: u-derivatives divided by spacing^k
};
PositionSegmentState EvaluatePositionSegment(const std::array<Eigen::Vector3d, 4>& control, double u,
                                             double spacing_seconds);

struct RotationSegmentState {
  SO3 rotation;
  Eigen::Vector3d angular_velocity;      // omega with R^T dR/dt = Hat(omega): the moving frame's own axes
  Eigen::Vector3d angular_acceleration;  // d omega / dt, same axes
};
RotationSegmentState EvaluateRotationSegment(const std::array<SO3, 4>& control, double u,
                                             double spacing_seconds);

// Jacobians J_i of the spline rotation with respect to right perturbations of the control rotations: to first
// order, R(u; R_i Exp(delta_i)) = R(u) Exp(sum_i J_i delta_i).
std::array<Eigen::Matrix3d, 4> RotationSegmentJacobians(const std::array<SO3, 4>& control, double u);

}  // namespace uf::spline
