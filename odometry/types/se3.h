// Rigid transforms (the Lie group SE(3)) on Eigen. A twist xi = [rho; phi] puts the translation part first;
// Exp gives R = Exp(phi), t = Jl(phi) rho. Jacobians follow Barfoot, "State Estimation for Robotics" (2017),
// section 7.1.5: Exp(xi + d) ~= Exp(xi) Exp(Jr(xi) d) ~= Exp(Jl(xi) d) Exp(xi), with Jl(xi) = Jr(-xi).
#pragma once

#include <Eigen/Core>

#include "odometry/types/so3.h"

namespace uf {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// T maps a point from the child frame to the parent frame: p_parent = R p_child + t. Named by frames,
// e.g. T_world_body.
class SE3 {
 public:
  SE3();  // identity
  SE3(const SO3& R, const Eigen::Vector3d& t);

  // Top-left 3x3 block stored as given (see SO3), last column as translation; the last row is ignored.
  static SE3 FromMatrix(const Eigen::Matrix4d& T);

  static SE3 Exp(const Vector6d& xi);  // xi = [rho; phi]
  Vector6d Log() const;

  Eigen::Matrix4d matrix() const;
  Eigen::Matrix<double, 3, 4> matrix3x4() const;  // [R | t], a KITTI pose line
  const SO3& so3() const { return R_; }
  const Eigen::Matrix3d& rotation() const { return R_.matrix(); }
  const Eigen::Vector3d& translation() const { return t_; }

  SE3 inverse() const;  // [R^T, -R^T t]
  SE3 operator*(const SE3& o) const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const;

  // Ad(T) with T Exp(xi) T^-1 = Exp(Ad(T) xi); for xi = [rho; phi]: [[R, Hat(t) R], [0, R]].
  Matrix6d Adjoint() const;

 private:
  SO3 R_;
  Eigen::Vector3d t_;
};

// Closed forms: Jl(xi) = [[Jl(phi), Q(rho, phi)], [0, Jl(phi)]] with Barfoot's Q, and Jr(xi) = Jl(-xi).
Matrix6d RightJacobianSE3(const Vector6d& xi);
Matrix6d LeftJacobianSE3(const Vector6d& xi);
Matrix6d RightJacobianInverseSE3(const Vector6d& xi);
Matrix6d LeftJacobianInverseSE3(const Vector6d& xi);

// Rotation by Slerp, translation linearly: the per-point pose used to deskew a scan (Ultra-Fusion paper).
// s in [0, 1]; s = 0 gives a, s = 1 gives b.
SE3 Interpolate(const SE3& a, const SE3& b, double s);

}  // namespace uf
