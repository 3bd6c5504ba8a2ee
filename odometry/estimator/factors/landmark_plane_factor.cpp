#include "odometry/estimator/factors/landmark_plane_factor.h"

#include <cassert>

#include "odometry/estimator/factors/interpolated_point.h"
#include "odometry/types/so3.h"

namespace uf::estimator {

using RowVector6d = Eigen::Matrix<double, 1, 6>;

LandmarkPlaneFactor::LandmarkPlaneFactor(const FeatureObservation& anchor, double td0, const Plane& plane)
    : anchor_(anchor), td0_(td0), plane_(plane) {
  assert(plane.sigma > 0);
}

bool LandmarkPlaneFactor::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  return EvaluateLiftingPoses(*this, 1, 2, 4, parameters, residuals, jacobians);
}

bool LandmarkPlaneFactor::EvaluateTangent(double const* const* parameters, double* residuals,
                                          double** jacobians) const {
  const Eigen::Matrix3d R_i = RotationOfPoseBlock(parameters[0]), R_bc = RotationOfPoseBlock(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> t_i(parameters[0]), t_bc(parameters[1]);
  const double lambda = parameters[2][0], td = parameters[3][0];
  const Eigen::Vector2d u = anchor_.normalized - (td - td0_) * anchor_.velocity;
  const Eigen::Vector3d P_c = Eigen::Vector3d(u.x(), u.y(), 1.0) / lambda;
  const Eigen::Vector3d P_b = R_bc * P_c + t_bc;
  const Eigen::Vector3d P_w = R_i * P_b + t_i;
  const Eigen::RowVector3d m = plane_.normal.transpose() / plane_.sigma;
  residuals[0] = m.dot((P_w - plane_.point).transpose());
  if (jacobians == nullptr) return true;
  const Eigen::RowVector3d m_Ri = m * R_i;
  const Eigen::RowVector3d m_Ri_Rbc = m_Ri * R_bc;
  if (jacobians[0] != nullptr) Eigen::Map<RowVector6d>(jacobians[0]) << m, -m_Ri * Hat(P_b);
  if (jacobians[1] != nullptr) Eigen::Map<RowVector6d>(jacobians[1]) << m_Ri, -m_Ri_Rbc * Hat(P_c);
  if (jacobians[2] != nullptr) jacobians[2][0] = -m_Ri_Rbc.dot(P_c) / lambda;
  if (jacobians[3] != nullptr)
    jacobians[3][0] =
        -m_Ri_Rbc.dot(Eigen::RowVector3d(anchor_.velocity.x(), anchor_.velocity.y(), 0.0)) / lambda;
  return true;
}

}  // namespace uf::estimator
