// The pose manifold against numeric derivatives: Plus/Minus invert each other, PlusJacobian is the derivative
// of Plus, MinusJacobian its pseudo-inverse, and lifted tangent Jacobians give back the tangent Jacobian.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

using Matrix76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using Matrix67 = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;

std::array<double, 7> RandomPose(std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  const Eigen::Vector3d phi(normal(random), normal(random), normal(random));
  return PoseBlock(SE3(SO3::Exp(phi), Eigen::Vector3d(normal(random), normal(random), normal(random))));
}

TEST(PoseManifold, PlusAndMinusAreInverseAndMatchSE3) {
  std::mt19937_64 random(3);
  const PoseManifold manifold;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = RandomPose(random);
    const double delta[6] = {0.3, -0.2, 0.1, 0.4, -0.5, 0.2};
    double y[7], back[6];
    manifold.Plus(x.data(), delta, y);
    manifold.Minus(y, x.data(), back);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], delta[i], 1e-12);
    // Right-multiplicative rotation, additive translation.
    const SE3 expected(PoseFromBlock(x.data()).so3() * SO3::Exp(Eigen::Vector3d(0.4, -0.5, 0.2)),
                       PoseFromBlock(x.data()).translation() + Eigen::Vector3d(0.3, -0.2, 0.1));
    EXPECT_TRUE(PoseFromBlock(y).matrix().isApprox(expected.matrix(), 1e-12));
  }
}

TEST(PoseManifold, JacobiansMatchNumericDerivatives) {
  std::mt19937_64 random(5);
  const PoseManifold manifold;
  const double h = 1e-7;
  for (int trial = 0; trial < 10; ++trial) {
    const auto x = RandomPose(random);
    Matrix76 plus;
    manifold.PlusJacobian(x.data(), plus.data());
    Matrix76 numeric;
    for (int k = 0; k < 6; ++k) {
      double delta[6] = {0, 0, 0, 0, 0, 0}, forward[7], backward[7];
      delta[k] = h;
      manifold.Plus(x.data(), delta, forward);
      delta[k] = -h;
      manifold.Plus(x.data(), delta, backward);
      for (int i = 0; i < 7; ++i) numeric(i, k) = (forward[i] - backward[i]) / (2 * h);
    }
    EXPECT_LT((plus - numeric).norm(), 1e-7);
    Matrix67 minus;
    manifold.MinusJacobian(x.data(), minus.data());
    EXPECT_LT((minus * plus - Eigen::Matrix<double, 6, 6>::Identity()).norm(), 1e-12);
  }
}

TEST(PoseManifold, LiftedTangentJacobianComesBack) {
  std::mt19937_64 random(7);
  const auto x = RandomPose(random);
  Eigen::Matrix<double, 3, 6, Eigen::RowMajor> tangent =
      Eigen::Matrix<double, 3, 6, Eigen::RowMajor>::Random();
  Eigen::Matrix<double, 3, 7, Eigen::RowMajor> ambient;
  TangentToAmbientJacobian(x.data(), tangent.data(), 3, ambient.data());
  Matrix76 plus;
  PoseManifold().PlusJacobian(x.data(), plus.data());
  EXPECT_LT((ambient * plus - tangent).norm(), 1e-12);
}

}  // namespace
}  // namespace uf::estimator
