#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "odometry/types/lie_coefficients.h"
#include "odometry/types/so3.h"
#include "tests/unit/types/numeric_jacobian.h"

namespace uf {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using test::NumericJacobian;

constexpr double kPi = std::numbers::pi;
constexpr double kJacobianTolerance = 1e-8;  // central difference, h = 1e-6 (see numeric_jacobian.h)

// Rotation vectors whose angles straddle every series/closed-form switch (1e-4, 0.1, 0.5) and reach
// close to pi, each along a generic axis.
std::vector<Vector3d> TestRotationVectors() {
  const Vector3d axis = Vector3d(0.3, -0.5, 0.8).normalized();
  std::vector<Vector3d> phis;
  for (double theta : {0.0, 1e-9, 0.99e-4, 1.01e-4, 0.0999, 0.1001, 0.4999, 0.5001, 1.2, 2.5, 3.0}) {
    phis.push_back(theta * axis);
  }
  phis.push_back(Vector3d(1.0, 0.0, 0.0));
  return phis;
}

TEST(SO3Test, HatIsCrossProductAndVeeInvertsIt) {
  const Vector3d v(1.0, -2.0, 3.0), w(0.5, 0.25, -4.0);
  EXPECT_TRUE(Hat(v).isApprox(-Hat(v).transpose()));
  EXPECT_TRUE((Hat(v) * w).isApprox(v.cross(w)));
  EXPECT_TRUE(Vee(Hat(v)).isApprox(v));
}

TEST(SO3Test, ExpMatchesEigenAngleAxis) {
  const Vector3d axis = Vector3d(-1.0, 2.0, 0.5).normalized();
  for (double theta : {1e-12, 1e-6, 0.3, 2.0, kPi}) {
    const Matrix3d expected = Eigen::AngleAxisd(theta, axis).toRotationMatrix();
    EXPECT_TRUE(SO3::Exp(theta * axis).matrix().isApprox(expected, 1e-14)) << "theta " << theta;
  }
  EXPECT_EQ(SO3::Exp(Vector3d::Zero()).matrix(), Matrix3d::Identity());
}

TEST(SO3Test, LogInvertsExpNearZeroGenericAndNearPi) {
  // Axes with positive and negative dominant components: near pi the axis comes from the symmetric part
  // up to sign, and the sign must be recovered.
  for (const Vector3d& axis : {Vector3d(0.2, 0.9, -0.4).normalized(), Vector3d(-0.2, -0.9, 0.4).normalized(),
                               Vector3d(-0.8, 0.1, 0.3).normalized(), Vector3d(0.0, 0.0, -1.0)}) {
    for (double theta : {0.0, 1e-14, 1e-9, 1e-5, 0.99e-4, 1.01e-4, 0.5, 2.0, 2.0 * kPi / 3.0 - 1e-9,
                         2.0 * kPi / 3.0 + 1e-9, 3.0, kPi - 1e-6, kPi - 1e-9}) {
      const Vector3d phi = theta * axis;
      const Vector3d log = SO3::Exp(phi).Log();
      EXPECT_LT((log - phi).norm(), 1e-12) << "theta " << theta << " axis " << axis.transpose();
    }
  }
}

TEST(SO3Test, SeriesAndClosedFormsAgreeAtEachSwitch) {
  // Each coefficient switches from its Taylor series to its closed form at a threshold; just below and
  // just above it the two branches must agree far more tightly than the Jacobian tests can resolve.
  const auto expect_continuous = [](double (*coefficient)(double), double threshold) {
    const double below = coefficient(threshold * (1.0 - 1e-12));
    const double above = coefficient(threshold * (1.0 + 1e-12));
    EXPECT_NEAR(below, above, 1e-12 * std::abs(above)) << "threshold " << threshold;
  };
  expect_continuous(lie::SinOverTheta, lie::kSeriesBelow);
  expect_continuous(lie::OneMinusCosOverTheta2, 2 * lie::kSeriesBelow);
  expect_continuous(lie::ThetaMinusSinOverTheta3, lie::kSeriesBelow);
  expect_continuous(lie::JacobianInverseCoefficient, 0.1);
  expect_continuous(lie::CosCoefficientQ, 0.5);
  expect_continuous(lie::SinCoefficientQ, 0.5);
}

TEST(SO3Test, TheSeriesAreTheClosedFormsInLongDouble) {
  // Below kSeriesBelow the sine coefficients are series; against the closed forms in long double (64-bit
  // mantissa), within a few doubles' ulps. (theta - sin) / theta^3 cancels: from 0.05 on, long double
  // keeps it to 3e-16.
  for (double theta = 1e-3; theta < lie::kSeriesBelow; theta += 1e-3) {
    const long double t = theta;
    EXPECT_NEAR(lie::SinOverTheta(theta), static_cast<double>(std::sin(t) / t), 4e-16) << theta;
    if (theta < 0.05) continue;
    EXPECT_NEAR(lie::ThetaMinusSinOverTheta3(theta), static_cast<double>((t - std::sin(t)) / (t * t * t)),
                1e-15 / 6)
        << theta;
  }
}

TEST(SO3Test, LogAtExactlyPiGivesAnglePiAndReproducesTheMatrix) {
  for (const Vector3d& axis : {Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1),
                               Vector3d(1, 1, 1).normalized(), Vector3d(0.3, -0.5, 0.8).normalized()}) {
    const SO3 R = SO3::Exp(kPi * axis);
    const Vector3d log = R.Log();
    EXPECT_NEAR(log.norm(), kPi, 1e-12);
    EXPECT_NEAR(std::abs(log.normalized().dot(axis)), 1.0, 1e-12);
    EXPECT_TRUE(SO3::Exp(log).matrix().isApprox(R.matrix(), 1e-12));
  }
  const SO3 flip(Matrix3d(Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal()));
  EXPECT_NEAR(std::abs(flip.Log().x()), kPi, 1e-15);
  EXPECT_NEAR(flip.angle(), kPi, 1e-15);
}

TEST(SO3Test, MatrixIsStoredAsGivenAndNormalizedGivesNearestRotation) {
  // A KITTI-like rotation, orthonormal only to ~1e-7.
  Matrix3d almost = SO3::Exp(Vector3d(0.1, -0.2, 0.3)).matrix();
  almost(0, 1) += 3e-7;
  almost(2, 0) -= 2e-7;
  const SO3 R(almost);
  EXPECT_EQ(R.matrix(), almost);
  EXPECT_EQ(R.inverse().matrix(), Matrix3d(almost.transpose()));
  const Matrix3d normalized = R.Normalized().matrix();
  EXPECT_TRUE((normalized * normalized.transpose()).isIdentity(1e-14));
  EXPECT_NEAR(normalized.determinant(), 1.0, 1e-14);
  EXPECT_LT((normalized - almost).norm(), 1e-6);
  // A reflection is mapped to a proper rotation.
  EXPECT_NEAR(SO3(Matrix3d(-Matrix3d::Identity())).Normalized().matrix().determinant(), 1.0, 1e-14);
}

TEST(SO3Test, QuaternionRoundTripWithNonNegativeW) {
  const Eigen::Quaterniond q(-0.5, 0.5, -0.5, 0.5);  // w < 0 on purpose
  const SO3 R(q);
  EXPECT_TRUE(R.matrix().isApprox(q.toRotationMatrix()));
  const Eigen::Quaterniond back = R.quaternion();
  EXPECT_GE(back.w(), 0.0);
  EXPECT_TRUE(back.coeffs().isApprox(-q.coeffs()));
  // An unnormalised quaternion is normalised first.
  const Eigen::Quaterniond scaled(2.0, 0.0, 0.0, 2.0);
  EXPECT_TRUE(SO3(scaled).matrix().isApprox(SO3::Exp(Vector3d(0, 0, kPi / 2)).matrix()));
}

TEST(SO3Test, GroupOperationsAndAngle) {
  const SO3 a = SO3::Exp(Vector3d(0.3, 0.1, -0.2)), b = SO3::Exp(Vector3d(-1.0, 0.4, 0.7));
  const Vector3d v(1.0, 2.0, 3.0);
  EXPECT_TRUE((a * b).matrix().isApprox(a.matrix() * b.matrix()));
  EXPECT_TRUE(((a * b) * v).isApprox(a * (b * v)));
  EXPECT_TRUE((a * a.inverse()).matrix().isIdentity(1e-15));
  EXPECT_NEAR(SO3::Exp(Vector3d(0.0, 1.25, 0.0)).angle(), 1.25, 1e-15);
  EXPECT_EQ(SO3().angle(), 0.0);
}

TEST(SO3Test, RightJacobianMatchesNumericDerivative) {
  // Exp(phi + d) = Exp(phi) Exp(Jr d): Jr = d/dd Log(Exp(phi)^-1 Exp(phi + d)) at d = 0.
  for (const Vector3d& phi : TestRotationVectors()) {
    const SO3 R_inv = SO3::Exp(phi).inverse();
    const auto f = [&](const Vector3d& d) { return Vector3d((R_inv * SO3::Exp(phi + d)).Log()); };
    const Matrix3d numeric = NumericJacobian<3, 3>(f, Vector3d::Zero());
    EXPECT_LT((RightJacobianSO3(phi) - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << phi.transpose();
  }
}

TEST(SO3Test, LeftJacobianMatchesNumericDerivative) {
  // Exp(phi + d) = Exp(Jl d) Exp(phi): Jl = d/dd Log(Exp(phi + d) Exp(phi)^-1) at d = 0.
  for (const Vector3d& phi : TestRotationVectors()) {
    const SO3 R_inv = SO3::Exp(phi).inverse();
    const auto f = [&](const Vector3d& d) { return Vector3d((SO3::Exp(phi + d) * R_inv).Log()); };
    const Matrix3d numeric = NumericJacobian<3, 3>(f, Vector3d::Zero());
    EXPECT_LT((LeftJacobianSO3(phi) - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << phi.transpose();
  }
}

TEST(SO3Test, RightJacobianInverseIsInverseAndMatchesNumericDerivative) {
  // Exp(phi) Exp(d) = Exp(phi + Jr^-1 d): Jr^-1 = d/dd Log(Exp(phi) Exp(d)) at d = 0.
  for (const Vector3d& phi : TestRotationVectors()) {
    const Matrix3d Jr_inv = RightJacobianInverseSO3(phi);
    EXPECT_TRUE((RightJacobianSO3(phi) * Jr_inv).isIdentity(1e-12)) << phi.transpose();
    const SO3 R = SO3::Exp(phi);
    const auto f = [&](const Vector3d& d) { return Vector3d((R * SO3::Exp(d)).Log()); };
    const Matrix3d numeric = NumericJacobian<3, 3>(f, Vector3d::Zero());
    EXPECT_LT((Jr_inv - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << phi.transpose();
  }
}

TEST(SO3Test, LeftJacobianInverseIsInverseAndMatchesNumericDerivative) {
  // Exp(d) Exp(phi) = Exp(phi + Jl^-1 d): Jl^-1 = d/dd Log(Exp(d) Exp(phi)) at d = 0.
  for (const Vector3d& phi : TestRotationVectors()) {
    const Matrix3d Jl_inv = LeftJacobianInverseSO3(phi);
    EXPECT_TRUE((LeftJacobianSO3(phi) * Jl_inv).isIdentity(1e-12)) << phi.transpose();
    const SO3 R = SO3::Exp(phi);
    const auto f = [&](const Vector3d& d) { return Vector3d((SO3::Exp(d) * R).Log()); };
    const Matrix3d numeric = NumericJacobian<3, 3>(f, Vector3d::Zero());
    EXPECT_LT((Jl_inv - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << phi.transpose();
  }
}

TEST(SO3Test, SlerpEndpointsAndMidpoint) {
  const SO3 a = SO3::Exp(Vector3d(kPi / 2, 0.0, 0.0));
  const SO3 b = a * SO3::Exp(Vector3d(0.0, 0.0, kPi / 2));
  EXPECT_TRUE(Slerp(a, b, 0.0).matrix().isApprox(a.matrix(), 1e-15));
  EXPECT_TRUE(Slerp(a, b, 1.0).matrix().isApprox(b.matrix(), 1e-15));
  // Halfway: a rotated a further 45 degrees about its own z axis; written out by hand:
  // Rx(90) = [1 0 0; 0 0 -1; 0 1 0], Rz(45) = [c -c 0; c c 0; 0 0 1] with c = sqrt(1/2).
  const double c = std::sqrt(0.5);
  Matrix3d expected;
  expected << c, -c, 0.0,  //
      0.0, 0.0, -1.0,      //
      c, c, 0.0;
  EXPECT_TRUE(Slerp(a, b, 0.5).matrix().isApprox(expected, 1e-15));
}

}  // namespace
}  // namespace uf
