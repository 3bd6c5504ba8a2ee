// The stereo factor at a landmark's anchor against independent truth: hand-computed residuals (with and
// without a time offset) and the analytic Jacobians (inverse depth, time offset) against central numeric
// derivatives, for random rigs and landmarks.
#include <gtest/gtest.h>

#include <random>

#include "odometry/estimator/factors/stereo_anchor_factor.h"

namespace uf::estimator {
namespace {

Eigen::Vector2d Residual(const StereoAnchorFactor& f, double lambda, double td) {
  const double* blocks[2] = {&lambda, &td};
  Eigen::Vector2d r;
  f.Evaluate(blocks, r.data(), nullptr);
  return r;
}

TEST(StereoAnchorFactor, ResidualIsTheSecondCamerasScaledError) {
  // The anchor camera sees u = (0.1, -0.2) at depth 2: P_c = (0.2, -0.4, 2). The right camera 0.5 m to its
  // right (p_right = p_left - (0.5, 0, 0)): P_r = (-0.3, -0.4, 2), pi = (-0.15, -0.2). Observed (-0.14,
  // -0.2), s = 100: r = (-1, 0).
  const SE3 T_right_left(SO3(), Eigen::Vector3d(-0.5, 0, 0));
  const StereoAnchorFactor still({{0.1, -0.2}, {0, 0}}, {-0.14, -0.2}, 0, 100, T_right_left);
  EXPECT_LT((Residual(still, 0.5, 0) - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
  // Moving at (1, 0)/s with t_d = 0.01 s (t_d0 = 0), both observations step back by (0.01, 0): u' = (0.09,
  // -0.2), P_c = (0.18, -0.4, 2), P_r = (-0.32, -0.4, 2), pi = (-0.16, -0.2); u_r' = (-0.15, -0.2):
  // r = 100 (-0.01, 0) = (-1, 0).
  const StereoAnchorFactor moving({{0.1, -0.2}, {1, 0}}, {-0.14, -0.2}, 0, 100, T_right_left);
  EXPECT_LT((Residual(moving, 0.5, 0.01) - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
}

TEST(StereoAnchorFactor, JacobiansMatchNumericDerivatives) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * s;
  };
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T_right_left(SO3::Exp(vec(0.05)), Eigen::Vector3d(-0.3, 0, 0) + vec(0.05));
    const Eigen::Vector3d P_c(normal(rng), normal(rng), 2 + 8 * std::abs(normal(rng)) / 3);
    const Eigen::Vector3d P_r = T_right_left * P_c;
    const FeatureObservation anchor{P_c.head<2>() / P_c.z(), Eigen::Vector2d(normal(rng), normal(rng)) * 0.3};
    const StereoAnchorFactor f(anchor, P_r.head<2>() / P_r.z() + Eigen::Vector2d(0.003, -0.002), 0.004, 300,
                               T_right_left);
    const double lambda = 1.1 / P_c.z(), td = -0.006;
    double J_lambda[2], J_td[2];
    double* jacobians[2] = {J_lambda, J_td};
    const double* blocks[2] = {&lambda, &td};
    Eigen::Vector2d r;
    ASSERT_TRUE(f.Evaluate(blocks, r.data(), jacobians));
    const double h = 1e-7;
    const Eigen::Vector2d numeric_lambda =
        (Residual(f, lambda + h, td) - Residual(f, lambda - h, td)) / (2 * h);
    const Eigen::Vector2d numeric_td = (Residual(f, lambda, td + h) - Residual(f, lambda, td - h)) / (2 * h);
    EXPECT_LT((Eigen::Vector2d(J_lambda[0], J_lambda[1]) - numeric_lambda).norm(),
              1e-5 * std::max(1.0, numeric_lambda.norm()))
        << "trial " << trial;
    EXPECT_LT((Eigen::Vector2d(J_td[0], J_td[1]) - numeric_td).norm(),
              1e-5 * std::max(1.0, numeric_td.norm()))
        << "trial " << trial;
    // The tangent interface is the same (both blocks are Euclidean).
    double T_lambda[2], T_td[2];
    double* tangent[2] = {T_lambda, T_td};
    f.EvaluateTangent(blocks, r.data(), tangent);
    EXPECT_EQ(T_lambda[0], J_lambda[0]);
    EXPECT_EQ(T_td[1], J_td[1]);
  }
}

}  // namespace
}  // namespace uf::estimator
