// Rotations in 3D (the Lie group SO(3)) on Eigen. phi in R^3 is a rotation vector (axis * angle, rad);
// Exp/Log map between the vector and the matrix. Jacobians follow Barfoot, "State Estimation for Robotics"
// (2017), section 7.1.5: the right Jacobian Jr satisfies Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d), the left
// Jacobian Jl satisfies Exp(phi + d) ~= Exp(Jl(phi) d) Exp(phi), and Jl(phi) = Jr(-phi) = Jr(phi)^T.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace uf {

// Hat(v) * w = v x w (the skew-symmetric cross-product matrix); Vee is its inverse (reads the skew part).
Eigen::Matrix3d Hat(const Eigen::Vector3d& v);
Eigen::Vector3d Vee(const Eigen::Matrix3d& m);

// A rotation matrix. The matrix is stored as given, without re-orthonormalisation, so that KITTI pose
// files whose rotations are orthonormal only to ~1e-7 are used exactly as evo uses them; call
// Normalized() for the nearest exact rotation.
class SO3 {
 public:
  SO3();  // identity
  explicit SO3(const Eigen::Matrix3d& R);
  explicit SO3(const Eigen::Quaterniond& q);  // normalises q first

  // Rodrigues' formula, with a Taylor branch for small angles.
  static SO3 Exp(const Eigen::Vector3d& phi);
  // Rotation vector with angle in [0, pi]; robust near 0 and near pi.
  Eigen::Vector3d Log() const;

  const Eigen::Matrix3d& matrix() const { return R_; }
  Eigen::Quaterniond quaternion() const;  // unit quaternion with w >= 0
  SO3 inverse() const;                    // the transpose (as evo's se3_inverse does)
  SO3 operator*(const SO3& o) const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& v) const;

  SO3 Normalized() const;  // nearest rotation in the Frobenius norm (SVD), det +1
  double angle() const;    // rotation angle in [0, pi]: acos(clamp((trace - 1) / 2))

 private:
  Eigen::Matrix3d R_;
};

Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi);

// Geodesic interpolation: a * Exp(s * Log(a^-1 b)), s in [0, 1] (s = 0 gives a, s = 1 gives b).
SO3 Slerp(const SO3& a, const SO3& b, double s);

}  // namespace uf
