#include "odometry/estimator/factors/stereo_anchor_factor.h"

#include <cassert>

namespace uf::estimator {

StereoAnchorFactor::StereoAnchorFactor(const FeatureObservation& anchor,
                                       const Eigen::Vector2d& right_normalized, double td0,
                                       double sqrt_information, const SE3& T_right_camera)
    : anchor_(anchor),
      right_(right_normalized),
      td0_(td0),
      sqrt_information_(sqrt_information),
      R_rc_(T_right_camera.so3().matrix()),
      t_rc_(T_right_camera.translation()) {
  assert(sqrt_information > 0);
}

bool StereoAnchorFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const double lambda = parameters[0][0], shift = parameters[1][0] - td0_;
  const Eigen::Vector2d u = anchor_.normalized - shift * anchor_.velocity;
  const Eigen::Vector2d u_r = right_ - shift * anchor_.velocity;
  const Eigen::Vector3d P_c = u.homogeneous() / lambda;
  const Eigen::Vector3d P_r = R_rc_ * P_c + t_rc_;
  const double z = P_r.z();
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = sqrt_information_ * (P_r.head<2>() / z - u_r);
  if (jacobians == nullptr) return true;
  Eigen::Matrix<double, 2, 3> D;
  D << 1 / z, 0, -P_r.x() / (z * z),  //
      0, 1 / z, -P_r.y() / (z * z);
  const Eigen::Matrix<double, 2, 3> sDR = sqrt_information_ * D * R_rc_;  // d r / d P_c
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Vector2d> J_lambda(jacobians[0]);
    J_lambda = -sDR * P_c / lambda;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Vector2d> J_td(jacobians[1]);
    const Eigen::Vector3d velocity(anchor_.velocity.x(), anchor_.velocity.y(), 0.0);
    J_td = -sDR * velocity / lambda + sqrt_information_ * anchor_.velocity;
  }
  return true;
}

}  // namespace uf::estimator
