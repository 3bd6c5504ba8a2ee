#include "odometry/estimator/factors/point_to_plane_factor.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>

#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/estimator/state/nav_state.h"
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
  return EvaluateLiftingPoses(*this, 1, 2, 2, parameters, residuals, jacobians);
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
  return EvaluateLiftingPoses(*this, 1, 1, 1, parameters, residuals, jacobians);
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

PointToPlaneLeverFactor::PointToPlaneLeverFactor(const Eigen::Vector3d& point_lidar, double alpha,
                                                 const Plane& plane, const Eigen::Matrix3d& R_body_lidar)
    : point_rotated_(R_body_lidar * point_lidar),
      alpha_(alpha),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(alpha >= 0 && alpha <= 1);
  assert(plane.sigma > 0);
}

bool PointToPlaneLeverFactor::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  return EvaluateLiftingPoses(*this, 1, 2, 3, parameters, residuals, jacobians);
}

bool PointToPlaneLeverFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                              double** jacobians) const {
  const double* pose_b = parameters[0];
  const double* pose_e = parameters[1];
  const Eigen::Vector3d point_body = point_rotated_ + Eigen::Map<const Eigen::Vector3d>(parameters[2]);
  const InterpolatedPoint point(SweepTermsAt(pose_b, pose_e), pose_b, pose_e, alpha_, point_body);
  residuals[0] = sqrt_information_ * normal_.dot(point.world() - plane_point_);
  if (jacobians == nullptr) return true;
  point.PullBack(sqrt_information_ * normal_.transpose(), jacobians[0], jacobians[1]);
  if (jacobians[2] != nullptr) {  // dp_w/dt_BL = R(a)
    Eigen::Map<Eigen::RowVector3d> J_t(jacobians[2]);
    J_t = sqrt_information_ * normal_.transpose() * point.rotation();
  }
  return true;
}

PointToPlaneLeverFactorSinglePose::PointToPlaneLeverFactorSinglePose(const Eigen::Vector3d& point_lidar,
                                                                     const Plane& plane,
                                                                     const Eigen::Matrix3d& R_body_lidar)
    : point_rotated_(R_body_lidar * point_lidar),
      normal_(plane.normal),
      plane_point_(plane.point),
      sqrt_information_(1.0 / plane.sigma) {
  assert(plane.sigma > 0);
}

bool PointToPlaneLeverFactorSinglePose::Evaluate(double const* const* parameters, double* residuals,
                                                 double** jacobians) const {
  return EvaluateLiftingPoses(*this, 1, 1, 2, parameters, residuals, jacobians);
}

bool PointToPlaneLeverFactorSinglePose::EvaluateTangent(double const* const* parameters, double* residuals,
                                                        double** jacobians) const {
  const double* pose = parameters[0];
  const Eigen::Map<const Eigen::Vector3d> t(pose);
  const Eigen::Matrix3d R = RotationOfPoseBlock(pose);
  const Eigen::Vector3d point_body = point_rotated_ + Eigen::Map<const Eigen::Vector3d>(parameters[1]);
  residuals[0] = sqrt_information_ * normal_.dot(R * point_body + t - plane_point_);
  if (jacobians == nullptr) return true;
  const Eigen::RowVector3d n_R = sqrt_information_ * normal_.transpose() * R;
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowVector6d> J(jacobians[0]);
    J << sqrt_information_ * normal_.transpose(), -n_R * Hat(point_body);
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::RowVector3d> J_t(jacobians[1]);
    J_t = n_R;
  }
  return true;
}

}  // namespace uf::estimator
