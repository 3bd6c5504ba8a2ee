// The wheel factor against independent truth: central differences in the pose tangent (Jacobians), the
// residual at the simulator's true motion, and a small solve that recovers a 10 % wheel scale error.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "odometry/estimator/factors/wheel_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/window/dense_least_squares.h"
#include "tests/unit/estimator/wheel_test_support.h"

namespace uf::estimator {
namespace {

using testing::ErrorBound;
using testing::Generate;
using testing::kMillisecond;
using testing::kRearAxle;
using testing::kSecond;
using testing::kTilted;
using testing::MotionErrors;
using testing::Preintegrate;
using testing::TruthSamples;
using testing::Wheel;

// The wheel factor's blocks.
struct Blocks {
  std::array<double, kPoseSize> pose_i, pose_j;
  double scale = 1.0;
  std::array<const double*, 3> pointers() const { return {pose_i.data(), pose_j.data(), &scale}; }
};

TEST(WheelFactor, JacobiansMatchCentralDifferencesInTheTangent) {
  // Random poses and mounts around the wild scene's motion, scale 1.07, against central differences of
  // Evaluate through PoseManifold::Plus; both the lifted ambient Jacobians (times PlusJacobian) and the
  // tangent ones.
  const sim::WheelSimulator wheel = Wheel("wild", kTilted, 50.0);
  const Stamp from = 6 * kSecond, to = 6 * kSecond + 400 * kMillisecond;
  const WheelPreintegration pre = Preintegrate(TruthSamples(Generate(wheel, from, to)), from, to);
  std::mt19937_64 random(17);
  std::normal_distribution<double> normal;
  const auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * s;
  };
  const PoseManifold manifold;
  for (int trial = 0; trial < 4; ++trial) {
    const SE3 T_imu_wheel(SO3::Exp(vec(0.5)), vec(0.5));
    const WheelFactor factor(pre, T_imu_wheel);
    Blocks x;
    x.pose_i = PoseBlock(SE3(SO3::Exp(vec(1.0)), vec(5.0)));
    x.pose_j = PoseBlock(PoseFromBlock(x.pose_i.data()) * SE3(SO3::Exp(vec(0.3)), vec(1.0)));
    x.scale = 1.07;
    const auto p = x.pointers();
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J_ambient[2];
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> J_tangent[2];
    Vector6d J_scale, J_scale_tangent, r, r_tangent;
    double* jacobians[3] = {J_ambient[0].data(), J_ambient[1].data(), J_scale.data()};
    double* tangent[3] = {J_tangent[0].data(), J_tangent[1].data(), J_scale_tangent.data()};
    ASSERT_TRUE(factor.Evaluate(p.data(), r.data(), jacobians));
    ASSERT_TRUE(factor.EvaluateTangent(p.data(), r_tangent.data(), tangent));
    EXPECT_EQ(r, r_tangent);
    const double h = 1e-6;
    for (int block = 0; block < 3; ++block) {
      const int size = block < 2 ? 6 : 1;
      Eigen::MatrixXd numeric(6, size);
      for (int k = 0; k < size; ++k) {
        Vector6d r_side[2];
        for (int side = 0; side < 2; ++side) {
          Blocks moved = x;
          const double step = side == 0 ? h : -h;
          if (block == 2) {
            moved.scale += step;
          } else {
            double delta[6] = {0, 0, 0, 0, 0, 0};
            delta[k] = step;
            auto& pose = block == 0 ? moved.pose_i : moved.pose_j;
            const auto original = pose;
            manifold.Plus(original.data(), delta, pose.data());
          }
          const auto q = moved.pointers();
          ASSERT_TRUE(factor.Evaluate(q.data(), r_side[side].data(), nullptr));
        }
        numeric.col(k) = (r_side[0] - r_side[1]) / (2 * h);
      }
      Eigen::MatrixXd analytic, analytic_tangent;
      if (block < 2) {
        Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
        manifold.PlusJacobian(p[block], plus.data());
        analytic = J_ambient[block] * plus;
        analytic_tangent = J_tangent[block];
      } else {
        analytic = J_scale;
        analytic_tangent = J_scale_tangent;
      }
      EXPECT_LT((analytic - numeric).norm(), 1e-6 * numeric.norm()) << "block " << block << "\nanalytic\n"
                                                                    << analytic << "\nnumeric\n"
                                                                    << numeric;
      EXPECT_LT((analytic_tangent - analytic).norm(), 1e-9 * numeric.norm()) << "block " << block;
    }
  }
}

// The factor's blocks at the true imu poses of the simulator (body = imu) and scale s.
Blocks TrueBlocks(const sim::WheelSimulator& wheel, Stamp from, Stamp to, double scale = 1.0) {
  Blocks x;
  x.pose_i = PoseBlock(wheel.trajectory().Pose(from));
  x.pose_j = PoseBlock(wheel.trajectory().Pose(to));
  x.scale = scale;
  return x;
}

TEST(WheelFactor, ResidualAtTheTrueMotionIsSmall) {
  // Full true twist: the unweighted residual is the integration error, within its bound (test above). The
  // odometry's own samples (v_x, 0, 0), (0, 0, w_z) miss the lateral velocity of the rear axle behind the
  // imu, and the roll, pitch and vertical motion of the scene (over 1 s up to 0.3 m vertically and 0.09 rad
  // of roll in the wild scene): the soft rows take them, so the whitened residual stays within the 6-dof
  // chi-square range (|r|^2 < 16.8 at 99 %; measured at most 5.1, on the wild scene over 0.1 s, with the
  // default noise of a road car's suspension, which grows with the speed: wheel_factor_config.h). The forward
  // distance and the yaw stay within one standard deviation of their firm noise (wild over 1 s: 7.5 mm
  // against 5 cm, 5.9 mrad against 10 mrad, the yaw that the unmeasured roll and pitch rates turn), and on
  // the flatter urban scene within 1 mm and 0.5 mrad (measured 0.45 mm, 0.42 mrad).
  for (const char* scene : {"urban", "wild"}) {
    const sim::WheelSimulator wheel = Wheel(scene, kRearAxle, 50.0);
    const sim::SimulatedWheel simulated = Generate(wheel, 2 * kSecond, 10 * kSecond);
    const std::vector<WheelSample> truth = TruthSamples(simulated);
    for (const Stamp length : {kSecond / 10, kSecond}) {
      for (Stamp from = 3 * kSecond; from + length <= 9 * kSecond; from += 1300 * kMillisecond) {
        const Stamp to = from + length;
        const Blocks x = TrueBlocks(wheel, from, to);
        const auto p = x.pointers();
        const WheelFactor exact(Preintegrate(truth, from, to), kRearAxle);
        const Vector6d r_exact = exact.Residual(p[0], p[1], 1.0);
        const MotionErrors bound = ErrorBound(wheel, from, to, 0.02);
        EXPECT_LT(r_exact.head<3>().norm(), 1.5 * bound.position) << scene << " at " << from;
        EXPECT_LT(r_exact.tail<3>().norm(), 1.5 * bound.rotation) << scene << " at " << from;
        const WheelFactor measured(Preintegrate(simulated.samples, from, to), kRearAxle);
        const Vector6d r = measured.Residual(p[0], p[1], 1.0);
        Vector6d weighted;
        ASSERT_TRUE(measured.Evaluate(p.data(), weighted.data(), nullptr));
        EXPECT_LT(weighted.squaredNorm(), 16.8) << scene << " " << from << ": r = " << r.transpose();
        const Vector6d sd = measured.preintegration().covariance().diagonal().cwiseSqrt();
        const double forward = std::abs(r[kWheelPosition]), yaw = std::abs(r[kWheelRotation + 2]);
        EXPECT_LT(forward, sd[kWheelPosition]) << scene << " forward at " << from;
        EXPECT_LT(yaw, sd[kWheelRotation + 2]) << scene << " yaw at " << from;
        if (scene == std::string("urban")) {
          EXPECT_LT(forward, 1e-3) << "forward at " << from;
          EXPECT_LT(yaw, 5e-4) << "yaw at " << from;
        }
      }
    }
  }
}

TEST(WheelFactor, TinySolveRecoversATenPercentScaleError) {
  // The odometry computes with a wheel radius and baseline both 1/1.1 of the truth: the reported speed is
  // v / 1.1, the yaw rate right, so the true scale is 1.1. Poses held at the truth; only the scale block is
  // free, starting at 1, with its prior (sigma 0.05) pulling towards 1 with ~1e-3 of the data's weight.
  sim::WheelConfig biased;
  biased.radius_error = biased.baseline_error = 1.0 / 1.1 - 1.0;
  const sim::WheelSimulator wheel = Wheel("urban", kRearAxle, 50.0, biased);
  const sim::SimulatedWheel simulated = Generate(wheel, 2 * kSecond, 9 * kSecond);
  const WheelFactorConfig config;
  std::vector<Blocks> blocks;
  std::vector<std::unique_ptr<WheelFactor>> factors;
  for (Stamp from = 3 * kSecond; from < 8 * kSecond; from += kSecond / 10) {
    blocks.push_back(TrueBlocks(wheel, from, from + kSecond / 10));
    factors.push_back(std::make_unique<WheelFactor>(
        Preintegrate(simulated.samples, from, from + kSecond / 10, config), kRearAxle));
  }
  double scale = 1.0;
  const WheelScalePriorFactor prior(config.scale_prior_sigma);
  DenseLeastSquares problem;
  problem.AddEuclideanBlock(&scale, 1);
  for (std::size_t k = 0; k < factors.size(); ++k)
    problem.AddResidualBlock(factors[k].get(), nullptr,
                             {blocks[k].pose_i.data(), blocks[k].pose_j.data(), &scale});
  problem.AddResidualBlock(&prior, nullptr, {&scale});
  DenseSolverOptions options;
  options.max_iterations = 20;
  options.max_time_s = 10.0;
  const DenseSolverSummary summary = problem.Solve(options);
  ASSERT_TRUE(summary.usable);
  EXPECT_LT(summary.final_cost, 0.02 * summary.initial_cost);  // left: the prior, the planar model's misfit
  EXPECT_NEAR(scale, 1.1, 2e-3);
  std::cout << "scale " << scale << " after " << summary.iterations << " iterations, cost "
            << summary.initial_cost << " -> " << summary.final_cost << "\n";
}

TEST(WheelScalePriorFactor, IsTheRelativeErrorOverSigma) {
  const WheelScalePriorFactor prior(0.05);
  const double scale = 1.1;
  const double* parameters[1] = {&scale};
  double r = 0, J = 0;
  double* jacobians[1] = {&J};
  ASSERT_TRUE(prior.Evaluate(parameters, &r, jacobians));
  EXPECT_NEAR(r, 2.0, 1e-12);
  EXPECT_NEAR(J, 20.0, 1e-12);
}

}  // namespace
}  // namespace uf::estimator
