#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "odometry/types/se3.h"
#include "tests/unit/types/numeric_jacobian.h"

namespace uf {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using test::NumericJacobian;

constexpr double kPi = std::numbers::pi;
constexpr double kJacobianTolerance = 1e-8;  // central difference, h = 1e-6 (see numeric_jacobian.h)

Vector6d Twist(const Vector3d& rho, const Vector3d& phi) {
  Vector6d xi;
  xi << rho, phi;
  return xi;
}

// Twists whose rotation angles straddle every series/closed-form switch (1e-4, 0.1, 0.5) and reach 3.0.
std::vector<Vector6d> TestTwists() {
  const Vector3d axis = Vector3d(-0.6, 0.2, 0.7).normalized();
  const Vector3d rho(1.5, -0.7, 2.0);
  std::vector<Vector6d> xis;
  for (double theta : {0.0, 1e-9, 0.99e-4, 1.01e-4, 0.0999, 0.1001, 0.4999, 0.5001, 1.2, 2.5, 3.0}) {
    xis.push_back(Twist(rho, theta * axis));
  }
  return xis;
}

TEST(SE3Test, ExpOfAQuarterTurnMatchesHandComputation) {
  // phi = (pi/2) e_z, rho = e_x: t = Jl(phi) rho = (sin(theta)/theta) e_x + ((1 - cos(theta))/theta) e_y
  //   = (2/pi, 2/pi, 0).
  const SE3 T = SE3::Exp(Twist(Vector3d(1, 0, 0), Vector3d(0, 0, kPi / 2)));
  EXPECT_TRUE(T.translation().isApprox(Vector3d(2 / kPi, 2 / kPi, 0), 1e-15));
  EXPECT_TRUE((T.so3() * Vector3d(1, 0, 0)).isApprox(Vector3d(0, 1, 0), 1e-15));
  // Pure translation: t = rho.
  EXPECT_TRUE(SE3::Exp(Twist(Vector3d(1, 2, 3), Vector3d::Zero())).translation().isApprox(Vector3d(1, 2, 3)));
}

TEST(SE3Test, LogInvertsExpNearZeroGenericAndNearPi) {
  const Vector3d axis = Vector3d(0.5, -0.5, 0.7).normalized();
  const Vector3d rho(-3.0, 0.5, 1.0);
  for (double theta : {0.0, 1e-12, 1e-6, 0.3, 2.0, 3.0, kPi - 1e-6}) {
    const Vector6d xi = Twist(rho, theta * axis);
    EXPECT_LT((SE3::Exp(xi).Log() - xi).norm(), 1e-10) << "theta " << theta;
  }
}

TEST(SE3Test, MatrixFormsAndFromMatrixKeepTheRotationAsGiven) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = SO3::Exp(Vector3d(0.2, 0.3, -0.1)).matrix();
  M(0, 1) += 4e-7;  // orthonormal only to ~1e-7, as in KITTI pose files
  M.topRightCorner<3, 1>() = Vector3d(1.0, 2.0, 3.0);
  const SE3 T = SE3::FromMatrix(M);
  EXPECT_EQ(T.matrix(), M);
  EXPECT_EQ(T.matrix3x4(), M.topRows<3>());
  EXPECT_EQ(T.rotation(), Matrix3d(M.topLeftCorner<3, 3>()));
}

TEST(SE3Test, CompositionInverseAndPointTransform) {
  const SE3 a = SE3::Exp(Twist(Vector3d(1, 2, 3), Vector3d(0.1, -0.4, 0.3)));
  const SE3 b = SE3::Exp(Twist(Vector3d(-2, 0, 1), Vector3d(1.0, 0.5, -0.2)));
  const Vector3d p(0.3, -1.0, 4.0);
  EXPECT_TRUE((a * b).matrix().isApprox(a.matrix() * b.matrix()));
  EXPECT_TRUE(((a * b) * p).isApprox(a * (b * p)));
  EXPECT_TRUE((a * p).isApprox(a.rotation() * p + a.translation()));
  EXPECT_TRUE((a * a.inverse()).matrix().isIdentity(1e-14));
  EXPECT_TRUE((a.inverse() * (a * p)).isApprox(p));
}

TEST(SE3Test, AdjointMovesATwistAcrossATransform) {
  // T Exp(xi) T^-1 = Exp(Ad(T) xi)
  const SE3 T = SE3::Exp(Twist(Vector3d(0.5, -1.0, 2.0), Vector3d(0.7, 0.2, -0.9)));
  for (const Vector6d& xi : TestTwists()) {
    const Eigen::Matrix4d lhs = (T * SE3::Exp(xi) * T.inverse()).matrix();
    const Eigen::Matrix4d rhs = SE3::Exp(T.Adjoint() * xi).matrix();
    EXPECT_LT((lhs - rhs).cwiseAbs().maxCoeff(), 1e-12) << xi.transpose();
  }
}

TEST(SE3Test, RightJacobianMatchesNumericDerivative) {
  // Exp(xi + d) = Exp(xi) Exp(Jr d): Jr = d/dd Log(Exp(xi)^-1 Exp(xi + d)) at d = 0.
  for (const Vector6d& xi : TestTwists()) {
    const SE3 T_inv = SE3::Exp(xi).inverse();
    const auto f = [&](const Vector6d& d) { return Vector6d((T_inv * SE3::Exp(xi + d)).Log()); };
    const Matrix6d numeric = NumericJacobian<6, 6>(f, Vector6d::Zero());
    EXPECT_LT((RightJacobianSE3(xi) - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << xi.transpose();
  }
}

TEST(SE3Test, LeftJacobianMatchesNumericDerivative) {
  // Exp(xi + d) = Exp(Jl d) Exp(xi): Jl = d/dd Log(Exp(xi + d) Exp(xi)^-1) at d = 0.
  for (const Vector6d& xi : TestTwists()) {
    const SE3 T_inv = SE3::Exp(xi).inverse();
    const auto f = [&](const Vector6d& d) { return Vector6d((SE3::Exp(xi + d) * T_inv).Log()); };
    const Matrix6d numeric = NumericJacobian<6, 6>(f, Vector6d::Zero());
    EXPECT_LT((LeftJacobianSE3(xi) - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << xi.transpose();
  }
}

TEST(SE3Test, RightJacobianInverseIsInverseAndMatchesNumericDerivative) {
  // Exp(xi) Exp(d) = Exp(xi + Jr^-1 d): Jr^-1 = d/dd Log(Exp(xi) Exp(d)) at d = 0.
  for (const Vector6d& xi : TestTwists()) {
    const Matrix6d Jr_inv = RightJacobianInverseSE3(xi);
    EXPECT_TRUE((RightJacobianSE3(xi) * Jr_inv).isIdentity(1e-12)) << xi.transpose();
    const SE3 T = SE3::Exp(xi);
    const auto f = [&](const Vector6d& d) { return Vector6d((T * SE3::Exp(d)).Log()); };
    const Matrix6d numeric = NumericJacobian<6, 6>(f, Vector6d::Zero());
    EXPECT_LT((Jr_inv - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << xi.transpose();
  }
}

TEST(SE3Test, LeftJacobianInverseIsInverseAndMatchesNumericDerivative) {
  // Exp(d) Exp(xi) = Exp(xi + Jl^-1 d): Jl^-1 = d/dd Log(Exp(d) Exp(xi)) at d = 0.
  for (const Vector6d& xi : TestTwists()) {
    const Matrix6d Jl_inv = LeftJacobianInverseSE3(xi);
    EXPECT_TRUE((LeftJacobianSE3(xi) * Jl_inv).isIdentity(1e-12)) << xi.transpose();
    const SE3 T = SE3::Exp(xi);
    const auto f = [&](const Vector6d& d) { return Vector6d((SE3::Exp(d) * T).Log()); };
    const Matrix6d numeric = NumericJacobian<6, 6>(f, Vector6d::Zero());
    EXPECT_LT((Jl_inv - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << xi.transpose();
  }
}

TEST(SE3Test, InterpolateEndpointsAndMidpoint) {
  const SE3 a(SO3(), Vector3d(0.0, 0.0, 0.0));
  const SE3 b(SO3::Exp(Vector3d(0.0, 0.0, kPi / 2)), Vector3d(2.0, 4.0, -6.0));
  EXPECT_TRUE(Interpolate(a, b, 0.0).matrix().isApprox(a.matrix(), 1e-15));
  EXPECT_TRUE(Interpolate(a, b, 1.0).matrix().isApprox(b.matrix(), 1e-15));
  // Halfway: 45 degrees about z and the translation midpoint (not the screw motion's midpoint).
  const double c = std::sqrt(0.5);
  Eigen::Matrix4d expected;
  expected << c, -c, 0.0, 1.0,  //
      c, c, 0.0, 2.0,           //
      0.0, 0.0, 1.0, -3.0,      //
      0.0, 0.0, 0.0, 1.0;
  EXPECT_TRUE(Interpolate(a, b, 0.5).matrix().isApprox(expected, 1e-15));
}

}  // namespace
}  // namespace uf
