#include "odometry/types/so3.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "odometry/types/lie_coefficients.h"

namespace uf {

Eigen::Matrix3d Hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Vector3d Vee(const Eigen::Matrix3d& m) {
  // Averages the two entries of each skew pair, so a non-skew matrix gives the vee of its skew part.
  return 0.5 * Eigen::Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

SO3::SO3() : R_(Eigen::Matrix3d::Identity()) {}

SO3::SO3(const Eigen::Matrix3d& R) : R_(R) {}

SO3::SO3(const Eigen::Quaterniond& q) : R_(q.normalized().toRotationMatrix()) {}

SO3 SO3::Exp(const Eigen::Vector3d& phi) {
  // Rodrigues: R = I + sin(theta)/theta K + (1 - cos(theta))/theta^2 K^2, K = Hat(phi).
  const double theta = phi.norm();
  const Eigen::Matrix3d K = Hat(phi);
  return SO3(Eigen::Matrix3d::Identity() + lie::SinOverTheta(theta) * K +
             lie::OneMinusCosOverTheta2(theta) * K * K);
}

Eigen::Vector3d SO3::Log() const {
  // R - R^T = 2 sin(theta) Hat(a) and trace(R) = 1 + 2 cos(theta), for the unit axis a. The angle comes
  // from atan2 of both, accurate everywhere; the axis from the skew part, except near pi where sin(theta)
  // vanishes and the symmetric part (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) a a^T is used.
  const Eigen::Vector3d w = Vee(R_);  // sin(theta) a
  const double sin_theta = w.norm();
  const double cos_theta = 0.5 * (R_.trace() - 1.0);
  const double theta = std::atan2(sin_theta, cos_theta);
  if (theta < 1e-4) {
    return (1.0 + theta * theta / 6.0) * w;  // theta / sin(theta), Taylor to second order
  }
  if (cos_theta > -0.5) {  // theta < 2 pi / 3: sin(theta) > 0.86, well conditioned
    return (theta / sin_theta) * w;
  }
  const Eigen::Matrix3d B = 0.5 * (R_ + R_.transpose()) - cos_theta * Eigen::Matrix3d::Identity();
  Eigen::Index i = 0;
  B.diagonal().maxCoeff(&i);
  Eigen::Vector3d axis = B.col(i).normalized();  // column i of a a^T is a_i a, the largest one
  if (axis.dot(w) < 0.0) axis = -axis;           // sign from sin(theta) a (arbitrary at exactly pi)
  return theta * axis;
}

Eigen::Quaterniond SO3::quaternion() const {
  Eigen::Quaterniond q(R_);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

SO3 SO3::inverse() const { return SO3(Eigen::Matrix3d(R_.transpose())); }

SO3 SO3::operator*(const SO3& o) const { return SO3(Eigen::Matrix3d(R_ * o.R_)); }

Eigen::Vector3d SO3::operator*(const Eigen::Vector3d& v) const { return R_ * v; }

SO3 SO3::Normalized() const {
  // Nearest orthogonal matrix U V^T; flipping the last singular direction keeps det = +1.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R_, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) D(2, 2) = -1.0;
  return SO3(Eigen::Matrix3d(svd.matrixU() * D * svd.matrixV().transpose()));
}

double SO3::angle() const { return std::acos(std::clamp(0.5 * (R_.trace() - 1.0), -1.0, 1.0)); }

// Jr(phi) = I - (1 - cos)/theta^2 K + (theta - sin)/theta^3 K^2 (Barfoot eq. 7.86 with phi -> -phi).
Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& phi) { return LeftJacobianSO3(-phi); }

Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& phi) { return LeftJacobianInverseSO3(-phi); }

// Jl(phi) = I + (1 - cos)/theta^2 K + (theta - sin)/theta^3 K^2, K = Hat(phi).
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = Hat(phi);
  return Eigen::Matrix3d::Identity() + lie::OneMinusCosOverTheta2(theta) * K +
         lie::ThetaMinusSinOverTheta3(theta) * K * K;
}

// Jl^-1(phi) = I - K/2 + (1/theta^2 - (1 + cos)/(2 theta sin)) K^2; singular at theta = 2 pi.
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = Hat(phi);
  return Eigen::Matrix3d::Identity() - 0.5 * K + lie::JacobianInverseCoefficient(theta) * K * K;
}

SO3 Slerp(const SO3& a, const SO3& b, double s) { return a * SO3::Exp(s * (a.inverse() * b).Log()); }

}  // namespace uf
