#include <gtest/gtest.h>

#include "odometry/sim/cumulative_spline.h"
#include "tests/unit/types/numeric_jacobian.h"

namespace uf::spline {
namespace {

using Eigen::Vector3d;
using Eigen::Vector4d;

std::array<SO3, 4> TestRotations() {
  return {SO3::Exp(Vector3d(0.3, -1.2, 2.0)), SO3::Exp(Vector3d(0.9, -0.8, 2.4)),
          SO3::Exp(Vector3d(1.1, 0.1, 2.9)),
          SO3::Exp(Vector3d(0.4, 0.6, -2.8))};  // consecutive relative angles up to ~1.3 rad
}

TEST(CumulativeSplineTest, WeightsAreTheCubicBSplineOnes) {
  // At u = 0 the uniform cubic B-spline weights are (1, 4, 1, 0) / 6; they sum to one and are >= 0 inside.
  EXPECT_TRUE(PositionWeights(0.0).isApprox(Vector4d(1.0, 4.0, 1.0, 0.0) / 6.0));
  EXPECT_TRUE(PositionWeights(1.0).isApprox(Vector4d(0.0, 1.0, 4.0, 1.0) / 6.0));
  for (double u : {0.0, 0.1, 0.37, 0.5, 0.99, 1.0}) {
    EXPECT_NEAR(PositionWeights(u).sum(), 1.0, 1e-15);
    EXPECT_GE(PositionWeights(u).minCoeff(), 0.0);
  }
}

TEST(CumulativeSplineTest, BasisDerivativesMatchNumericDifferences) {
  const double h = 1e-6;
  for (double u : {0.05, 0.3, 0.5, 0.8, 0.95}) {
    const CumulativeBasis basis = CumulativeBasisAt(u);
    const CumulativeBasis plus = CumulativeBasisAt(u + h), minus = CumulativeBasisAt(u - h);
    EXPECT_LT((basis.first - (plus.value - minus.value) / (2 * h)).norm(), 1e-9) << "u " << u;
    EXPECT_LT((basis.second - (plus.first - minus.first) / (2 * h)).norm(), 1e-9) << "u " << u;
  }
}

TEST(CumulativeSplineTest, LocateSegmentSplitsStampsExactly) {
  const Stamp begin = 5'000, spacing = 100;
  EXPECT_EQ(LocateSegment(begin, begin, spacing, 3).index, 0);
  EXPECT_EQ(LocateSegment(begin + 150, begin, spacing, 3).index, 1);
  EXPECT_DOUBLE_EQ(LocateSegment(begin + 150, begin, spacing, 3).u, 0.5);
  EXPECT_EQ(LocateSegment(begin + 200, begin, spacing, 3).index, 2);
  EXPECT_EQ(LocateSegment(begin + 200, begin, spacing, 3).u, 0.0);
  EXPECT_EQ(LocateSegment(begin + 300, begin, spacing, 3).index, 2);  // the end belongs to the last one
  EXPECT_EQ(LocateSegment(begin + 300, begin, spacing, 3).u, 1.0);
}

TEST(CumulativeSplineTest, RotationJacobiansMatchNumericDifferences) {
  const std::array<SO3, 4> control = TestRotations();
  for (double u : {0.0, 0.25, 0.6, 1.0}) {
    const SO3 nominal = EvaluateRotationSegment(control, u, 1.0).rotation;
    // eta(delta) = Log(R(u)^T R(u; R_i Exp(delta_i))), whose Jacobian at 0 is [J_0 .. J_3].
    const auto eta = [&](const Eigen::Matrix<double, 12, 1>& delta) {
      std::array<SO3, 4> perturbed = control;
      for (int i = 0; i < 4; ++i) perturbed[i] = control[i] * SO3::Exp(delta.segment<3>(3 * i));
      return Vector3d((nominal.inverse() * EvaluateRotationSegment(perturbed, u, 1.0).rotation).Log());
    };
    const Eigen::Matrix<double, 3, 12> numeric =
        test::NumericJacobian<3, 12>(eta, Eigen::Matrix<double, 12, 1>::Zero());
    const std::array<Eigen::Matrix3d, 4> analytic = RotationSegmentJacobians(control, u);
    for (int i = 0; i < 4; ++i) {
      EXPECT_LT((analytic[i] - numeric.middleCols<3>(3 * i)).cwiseAbs().maxCoeff(), 1e-8)
          << "u " << u << " control point " << i << "\nanalytic\n"
          << analytic[i] << "\nnumeric\n"
          << numeric.middleCols<3>(3 * i);
    }
  }
}

TEST(CumulativeSplineTest, EqualIncrementsTurnAtConstantRate) {
  // lambda_1 + lambda_2 + lambda_3 = 1 + u, so equal increments d give R(u) = R_0 Exp((1 + u) d): the body
  // turns at the constant rate d / spacing with no angular acceleration.
  const Vector3d d(0.2, -0.1, 0.3);
  const std::array<SO3, 4> control = {SO3(), SO3::Exp(d), SO3::Exp(2 * d), SO3::Exp(3 * d)};
  for (double u : {0.0, 0.4, 1.0}) {
    const RotationSegmentState state = EvaluateRotationSegment(control, u, 0.5);
    EXPECT_LT((state.rotation.matrix() - SO3::Exp((1.0 + u) * d).matrix()).norm(), 1e-14);
    EXPECT_LT((state.angular_velocity - d / 0.5).norm(), 1e-14);
    EXPECT_LT(state.angular_acceleration.norm(), 1e-14);
  }
}

}  // namespace
}  // namespace uf::spline
