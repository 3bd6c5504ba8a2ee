// Triangulation of a feature from its observations (docs/METHOD.md "Visual reprojection factor"): the linear
// (DLT) solution from N >= 2 rays, and the inverse depth of the point in its anchor camera, the visual
// factor's parameter.
//
// Each observation is a camera pose T_world_cam = (R, t) and the undistorted normalized coordinates u =
// (x/z, y/z) of the ray. With the world-to-camera rows P = [R^T | -R^T t] (P_1, P_2, P_3 its rows) and the
// homogeneous world point X, u x (P X) = 0 gives two independent rows per observation:
//   u_x P_3 X - P_1 X = 0,   u_y P_3 X - P_2 X = 0
// and X is the right singular vector of the stacked 2N x 4 matrix with the smallest singular value.
#pragma once

#include <Eigen/Core>
#include <span>

#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct Triangulation {
  Eigen::Vector3d point_world = Eigen::Vector3d::Zero();
  double min_depth_m = 0;       // smallest depth (camera z) over the observations
  double parallax_deg = 0;      // largest angle between two of the rays at the point
  double max_reprojection = 0;  // largest |pi(P_c) - u| over the observations, normalized units
};

// Fails (with the reason) for fewer than 2 observations, sizes that differ, a point at infinity or behind a
// camera (depth below min_depth_m), or rays closer than min_parallax_deg (the depth is then unobservable).
Expected<Triangulation> Triangulate(std::span<const SE3> T_world_cam,
                                    std::span<const Eigen::Vector2d> normalized,
                                    double min_parallax_deg = 1.0, double min_depth_m = 0.1);

// 1 / z of the point in the anchor camera (the factor's lambda); the caller checks z > 0 (Triangulate does).
double InverseDepth(const SE3& T_world_anchor_cam, const Eigen::Vector3d& point_world);

}  // namespace uf::estimator
