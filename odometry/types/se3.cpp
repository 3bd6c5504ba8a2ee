#include "odometry/types/se3.h"

#include "odometry/types/lie_coefficients.h"

namespace uf {
namespace {

// Barfoot's Q(rho, phi) (eq. 7.86b), the top-right block of the left Jacobian of SE(3):
//   Q = 1/2 P + a (F P + P F + F P F) + b (F F P + P F F - 3 F P F) + c (F P F F + F F P F),
//   P = Hat(rho), F = Hat(phi), a = (theta - sin)/theta^3, b = (theta^2 + 2 cos - 2)/(2 theta^4),
//   c = (2 theta - 3 sin + theta cos)/(2 theta^5).
Eigen::Matrix3d BarfootQ(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d P = Hat(rho);
  const Eigen::Matrix3d F = Hat(phi);
  const Eigen::Matrix3d FP = F * P;
  const Eigen::Matrix3d PF = P * F;
  const Eigen::Matrix3d FPF = FP * F;
  const double a = lie::ThetaMinusSinOverTheta3(theta);
  const double b = lie::CosCoefficientQ(theta);
  // c = (b + 3 (theta - sin - theta^3/6)/theta^5) / 2, each term from its series near 0.
  const double c = 0.5 * (b + 3.0 * lie::SinCoefficientQ(theta));
  return 0.5 * P + a * (FP + PF + FPF) + b * (F * FP + PF * F - 3.0 * FPF) + c * (FPF * F + F * FPF);
}

}  // namespace

SE3::SE3() : t_(Eigen::Vector3d::Zero()) {}

SE3::SE3(const SO3& R, const Eigen::Vector3d& t) : R_(R), t_(t) {}

SE3 SE3::FromMatrix(const Eigen::Matrix4d& T) {
  return SE3(SO3(Eigen::Matrix3d(T.topLeftCorner<3, 3>())), T.topRightCorner<3, 1>());
}

SE3 SE3::Exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  return SE3(SO3::Exp(phi), LeftJacobianSO3(phi) * rho);
}

Vector6d SE3::Log() const {
  // phi = Log(R), then invert t = Jl(phi) rho.
  const Eigen::Vector3d phi = R_.Log();
  Vector6d xi;
  xi << LeftJacobianInverseSO3(phi) * t_, phi;
  return xi;
}

Eigen::Matrix4d SE3::matrix() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R_.matrix();
  T.topRightCorner<3, 1>() = t_;
  return T;
}

Eigen::Matrix<double, 3, 4> SE3::matrix3x4() const {
  Eigen::Matrix<double, 3, 4> T;
  T << R_.matrix(), t_;
  return T;
}

SE3 SE3::inverse() const {
  const SO3 R_inv = R_.inverse();
  return SE3(R_inv, -(R_inv * t_));
}

SE3 SE3::operator*(const SE3& o) const { return SE3(R_ * o.R_, R_ * o.t_ + t_); }

Eigen::Vector3d SE3::operator*(const Eigen::Vector3d& p) const { return R_ * p + t_; }

Matrix6d SE3::Adjoint() const {
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = R_.matrix();
  ad.topRightCorner<3, 3>() = Hat(t_) * R_.matrix();
  ad.bottomRightCorner<3, 3>() = R_.matrix();
  return ad;
}

Matrix6d LeftJacobianSE3(const Vector6d& xi) {
  const Eigen::Matrix3d Jl = LeftJacobianSO3(xi.tail<3>());
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = Jl;
  J.topRightCorner<3, 3>() = BarfootQ(xi.head<3>(), xi.tail<3>());
  J.bottomRightCorner<3, 3>() = Jl;
  return J;
}

Matrix6d RightJacobianSE3(const Vector6d& xi) { return LeftJacobianSE3(-xi); }

// Block inverse of an upper block-triangular matrix: [[A, Q], [0, A]]^-1 = [[A^-1, -A^-1 Q A^-1], [0, A^-1]].
Matrix6d LeftJacobianInverseSE3(const Vector6d& xi) {
  const Eigen::Matrix3d Jl_inv = LeftJacobianInverseSO3(xi.tail<3>());
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = Jl_inv;
  J.topRightCorner<3, 3>() = -Jl_inv * BarfootQ(xi.head<3>(), xi.tail<3>()) * Jl_inv;
  J.bottomRightCorner<3, 3>() = Jl_inv;
  return J;
}

Matrix6d RightJacobianInverseSE3(const Vector6d& xi) { return LeftJacobianInverseSE3(-xi); }

SE3 Interpolate(const SE3& a, const SE3& b, double s) {
  return SE3(Slerp(a.so3(), b.so3(), s), (1.0 - s) * a.translation() + s * b.translation());
}

}  // namespace uf
