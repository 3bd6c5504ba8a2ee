#include "odometry/estimator/state/pose_manifold.h"

#include <Eigen/Geometry>

#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using Quaternion = Eigen::Map<const Eigen::Quaterniond>;  // coefficients (x, y, z, w), as the block

// d(q Exp(w))/dw at w = 0 in the (x, y, z, w) layout: with q Exp(w) ~ q (x) [w/2; 1],
// vec part 1/2 (q_w I + [q_v]x) w, scalar part -1/2 q_v . w.
Eigen::Matrix<double, 4, 3> QuaternionPlusJacobian(const Eigen::Quaterniond& q) {
  Eigen::Matrix<double, 4, 3> J;
  J.topRows<3>() = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + Hat(q.vec()));
  J.bottomRows<1>() = -0.5 * q.vec().transpose();
  return J;
}

}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Quaternion q(x + 3);
  const Eigen::Quaterniond dq(SO3::Exp(Eigen::Vector3d(delta[3], delta[4], delta[5])).matrix());
  Eigen::Map<Eigen::Quaterniond> out(x_plus_delta + 3);
  out = (q * dq).normalized();
  for (int i = 0; i < 3; ++i) x_plus_delta[i] = x[i] + delta[i];
  return true;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<4, 3>() = QuaternionPlusJacobian(Quaternion(x + 3));
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Quaternion qx(x + 3), qy(y + 3);
  const Eigen::Vector3d dtheta = SO3(Eigen::Quaterniond(qx.conjugate() * qy)).Log();
  for (int i = 0; i < 3; ++i) {
    y_minus_x[i] = y[i] - x[i];
    y_minus_x[3 + i] = dtheta[i];
  }
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  // The columns of the quaternion part of PlusJacobian are orthogonal with norm 1/2 for a unit quaternion,
  // so its pseudo-inverse is 4 J^T.
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<3, 4>() = 4.0 * QuaternionPlusJacobian(Quaternion(x + 3)).transpose();
  return true;
}

void TangentToAmbientJacobian(const double* pose, const double* J_tangent, int rows, double* J_ambient) {
  using RowMajor6 = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;
  using RowMajor7 = Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>;
  double minus[6 * 7];
  PoseManifold().MinusJacobian(pose, minus);
  Eigen::Map<RowMajor7>(J_ambient, rows, 7) = Eigen::Map<const RowMajor6>(J_tangent, rows, 6) *
                                              Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>>(minus);
}

}  // namespace uf::estimator
