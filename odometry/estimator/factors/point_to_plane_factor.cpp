#include "odometry/estimator/factors/point_to_plane_factor.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>

#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using RowVector6d = Eigen::Matrix<double, 1, 6>;

// What all points of a scan share at one value of its (begin, end) blocks (interpolated_point.h). Solvers
// evaluate every point of a scan at the same values, so each thread keeps the terms of the last pair it saw
// and recomputes them only when the values change.
struct SweepTerms {
  std::array<double, 2 * kPoseSize> values{};
  bool valid = false;
  PoseInterpolationTerms terms;
};

const PoseInterpolationTerms& SweepTermsAt(const double* pose_b, const double* pose_e) {
  thread_local SweepTerms sweep;
  if (sweep.valid && std::equal(pose_b, pose_b + kPoseSize, sweep.values.begin()) &&
      std::equal(pose_e, pose_e + kPoseSize, sweep.values.begin() + kPoseSize))
    return sweep.terms;
  std::copy(pose_b, pose_b + kPoseSize, sweep.values.begin());
  std::copy(pose_e, pose_e + kPoseSize, sweep.values.begin() + kPoseSize);
  ComputePoseInterpolationTerms(pose_b, pose_e, sweep.terms);
  sweep.valid = true;  // (non-finite values never compare equal: they are recomputed every time)
  return sweep.terms;
}

}  // namespace

PointToPlaneFactor::PointToPlaneFactor(const Eigen::Vector3d& point_lidar, double alpha, const Plane& plane,
                                       const SE3& T_body_lidar)
    : point_body_(T_body_lidar * point_lidar),
      alpha_(alpha),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(alpha >= 0 && alpha <= 1);
  assert(plane.sigma > 0);
}

bool PointToPlaneFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  if (jacobians == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J_b[6], J_e[6];
  double* tangent[2] = {jacobians[0] != nullptr ? J_b : nullptr, jacobians[1] != nullptr ? J_e : nullptr};
  EvaluateTangent(parameters, residuals, tangent);
  if (jacobians[0] != nullptr) TangentToAmbientJacobian(parameters[0], J_b, 1, jacobians[0]);
  if (jacobians[1] != nullptr) TangentToAmbientJacobian(parameters[1], J_e, 1, jacobians[1]);
  return true;
}

bool PointToPlaneFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  const double* pose_b = parameters[0];
  const double* pose_e = parameters[1];
  const InterpolatedPoint point(SweepTermsAt(pose_b, pose_e), pose_b, pose_e, alpha_, point_body_);
  residuals[0] = sqrt_information_ * normal_.dot(point.world() - plane_point_);
  if (jacobians == nullptr) return true;
  // dr/dp_w = n^T / sigma, through the interpolation to both blocks.
  point.PullBack(sqrt_information_ * normal_.transpose(), jacobians[0], jacobians[1]);
  return true;
}

PointToPlaneFactorSinglePose::PointToPlaneFactorSinglePose(const Eigen::Vector3d& point_body,
                                                           const Plane& plane)
    : point_body_(point_body),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(plane.sigma > 0);
}

bool PointToPlaneFactorSinglePose::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  if (jacobians == nullptr || jacobians[0] == nullptr) return EvaluateTangent(parameters, residuals, nullptr);
  double J[6];
  double* tangent[1] = {J};
  EvaluateTangent(parameters, residuals, tangent);
  TangentToAmbientJacobian(parameters[0], J, 1, jacobians[0]);
  return true;
}

bool PointToPlaneFactorSinglePose::EvaluateTangent(double const* const* parameters, double* residuals,
                                                   double** jacobians) const {
  const double* pose = parameters[0];
  const Eigen::Map<const Eigen::Vector3d> t(pose);
  const Eigen::Matrix3d R = RotationOfPoseBlock(pose);
  residuals[0] = sqrt_information_ * normal_.dot(R * point_body_ + t - plane_point_);
  if (jacobians == nullptr || jacobians[0] == nullptr) return true;
  Eigen::Map<RowVector6d> J(jacobians[0]);
  J << sqrt_information_ * normal_.transpose(),
      -sqrt_information_ * (normal_.transpose() * R) * Hat(point_body_);
  return true;
}

}  // namespace uf::estimator
