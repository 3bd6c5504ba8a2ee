// The IMU factor: zero residual at the true states, analytic Jacobians against central differences in the
// pose tangent (through PoseManifold::Plus) and Ceres' GradientChecker, re-integration beyond the bias
// thresholds, and a small window solve that converges to the truth from noisy initial values.
#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <random>

#include "odometry/estimator/factors/imu_factor.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "tests/unit/estimator/imu_test_support.h"

namespace uf::estimator {
namespace {

using testing::kSecond;
using testing::MovingImu;
using testing::Samples;
using testing::TrueState;

using testing::kAccelBias;
using testing::kGyroBias;

using Pose = std::array<double, kPoseSize>;
using SpeedBias = std::array<double, kSpeedBiasSize>;

struct Blocks {
  Pose pose_i, pose_j;
  SpeedBias speed_bias_i, speed_bias_j;
  std::array<const double*, 4> pointers() const {
    return {pose_i.data(), speed_bias_i.data(), pose_j.data(), speed_bias_j.data()};
  }
};

Blocks BlocksOf(const NavState& i, const NavState& j) {
  return {PoseBlock(i.T_world_imu), PoseBlock(j.T_world_imu), SpeedBiasBlock(i), SpeedBiasBlock(j)};
}

// The preintegration over [t_i, t_j] of ideal samples at the simulator's rate (with its constant biases),
// linearized at (accel_bias, gyro_bias).
ImuPreintegration Preintegrate(const ImuSimulator& imu, Stamp t_i, Stamp t_j,
                               const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) {
  auto pre =
      ImuPreintegration::Between(Samples(imu, t_i, t_j), t_i, t_j, accel_bias, gyro_bias, ImuNoiseParams());
  EXPECT_TRUE(pre.ok()) << pre.error();
  return std::move(pre).value();
}

ImuFactor MakeFactor(const ImuSimulator& imu, Stamp t_i, Stamp t_j, const Eigen::Vector3d& accel_bias,
                     const Eigen::Vector3d& gyro_bias) {
  return ImuFactor(Preintegrate(imu, t_i, t_j, accel_bias, gyro_bias));
}

ImuSimulator BiasedImu(double rate_hz) {
  ImuNoise noise;
  noise.initial_accel_bias = kAccelBias;
  noise.initial_gyro_bias = kGyroBias;
  return MovingImu(rate_hz, noise);
}

TEST(ImuFactor, ResidualIsZeroAtTheTrueStates) {
  // 20 kHz makes the midpoint error negligible (~1e-8 over 0.5 s).
  const ImuSimulator imu = BiasedImu(20000.0);
  const Stamp t_i = kSecond, t_j = 3 * kSecond / 2;
  const Blocks x =
      BlocksOf(TrueState(imu, t_i, kAccelBias, kGyroBias), TrueState(imu, t_j, kAccelBias, kGyroBias));
  const auto p = x.pointers();
  // At the true biases, and linearized away from them (the first-order update is exact to ~|db|^2).
  const ImuFactor at_truth = MakeFactor(imu, t_i, t_j, kAccelBias, kGyroBias);
  EXPECT_LT(at_truth.Residual(p[0], p[1], p[2], p[3]).norm(), 1e-6);
  const ImuFactor nearby = MakeFactor(imu, t_i, t_j, kAccelBias + Eigen::Vector3d(0.004, 0.0, -0.004),
                                      kGyroBias + Eigen::Vector3d(0.0, 0.0005, 0.0));
  EXPECT_LT(nearby.Residual(p[0], p[1], p[2], p[3]).norm(), 1e-6);
  // The whitened residual too (the information weights up to ~1e5 per unit).
  Vector15d weighted;
  EXPECT_TRUE(at_truth.Evaluate(p.data(), weighted.data(), nullptr));
  EXPECT_LT(weighted.norm(), 1e-2);
  // A wrong state j shows: 1 cm in position gives |r_p| = 1 cm.
  Blocks moved = x;
  moved.pose_j[1] += 0.01;
  const auto q = moved.pointers();
  EXPECT_NEAR(at_truth.Residual(q[0], q[1], q[2], q[3]).segment<3>(kImuPosition).norm(), 0.01, 1e-6);
}

// Perturbed states away from the truth so that every residual term and Jacobian block is non-trivial.
Blocks PerturbedBlocks(const ImuSimulator& imu, Stamp t_i, Stamp t_j, std::uint64_t seed, double bias_scale) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * s;
  };
  NavState i = TrueState(imu, t_i, kAccelBias, kGyroBias), j = TrueState(imu, t_j, kAccelBias, kGyroBias);
  for (NavState* s : {&i, &j}) {
    s->T_world_imu = SE3(s->T_world_imu.so3() * SO3::Exp(vec(0.1)), s->T_world_imu.translation() + vec(0.2));
    s->velocity += vec(0.2);
    s->accel_bias += vec(0.03 * bias_scale);
    s->gyro_bias += vec(0.003 * bias_scale);
  }
  return BlocksOf(i, j);
}

// Ambient Jacobians from Evaluate times PlusJacobian (the tangent Jacobian Ceres uses) against central
// differences of Evaluate through PoseManifold::Plus (pose) and plain steps (speed_bias).
void ExpectJacobiansMatchNumeric(const ImuFactor& factor, const Blocks& x) {
  const PoseManifold manifold;
  const auto p = x.pointers();
  Eigen::Matrix<double, 15, 7, Eigen::RowMajor> J_pose[2];
  Eigen::Matrix<double, 15, 9, Eigen::RowMajor> J_speed_bias[2];
  double* jacobians[4] = {J_pose[0].data(), J_speed_bias[0].data(), J_pose[1].data(), J_speed_bias[1].data()};
  Vector15d r;
  ASSERT_TRUE(factor.Evaluate(p.data(), r.data(), jacobians));
  ASSERT_TRUE(r.allFinite());
  const double h = 1e-6;
  for (int block = 0; block < 4; ++block) {
    const bool is_pose = block % 2 == 0;
    const int tangent_size = is_pose ? 6 : 9;
    Eigen::MatrixXd analytic;
    if (is_pose) {
      Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
      manifold.PlusJacobian(p[block], plus.data());
      analytic = J_pose[block / 2] * plus;
    } else {
      analytic = J_speed_bias[block / 2];
    }
    Eigen::MatrixXd numeric(15, tangent_size);
    for (int k = 0; k < tangent_size; ++k) {
      Vector15d r_plus, r_minus;
      for (const double sign : {1.0, -1.0}) {
        Blocks moved = x;
        double* target = block == 0   ? moved.pose_i.data()
                         : block == 1 ? moved.speed_bias_i.data()
                         : block == 2 ? moved.pose_j.data()
                                      : moved.speed_bias_j.data();
        if (is_pose) {
          double delta[6] = {0, 0, 0, 0, 0, 0};
          delta[k] = sign * h;
          Pose moved_pose;
          manifold.Plus(target, delta, moved_pose.data());
          std::copy(moved_pose.begin(), moved_pose.end(), target);
        } else {
          target[k] += sign * h;
        }
        const auto q = moved.pointers();
        factor.Evaluate(q.data(), (sign > 0 ? r_plus : r_minus).data(), nullptr);
      }
      numeric.col(k) = (r_plus - r_minus) / (2 * h);
    }
    EXPECT_LT((analytic - numeric).norm(), 1e-5 * numeric.norm()) << "block " << block << "\nanalytic\n"
                                                                  << analytic << "\nnumeric\n"
                                                                  << numeric;
  }
}

TEST(ImuFactor, JacobiansMatchCentralDifferencesInTheTangent) {
  const ImuSimulator imu = BiasedImu(200.0);
  const ImuFactor factor = MakeFactor(imu, kSecond, 2 * kSecond, kAccelBias, kGyroBias);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    ExpectJacobiansMatchNumeric(factor, PerturbedBlocks(imu, kSecond, 2 * kSecond, seed, 1.0));
  }
}

TEST(ImuFactor, PassesCeresGradientChecker) {
  const ImuSimulator imu = BiasedImu(200.0);
  const ImuFactor factor = MakeFactor(imu, kSecond, 3 * kSecond / 2, kAccelBias, kGyroBias);
  const Blocks x = PerturbedBlocks(imu, kSecond, 3 * kSecond / 2, 7, 1.0);
  const PoseManifold manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&manifold, nullptr, &manifold, nullptr};
  // Ceres' default Ridders start (1e-2 of the value) is too coarse for residuals whitened by weights up to
  // ~5e4 (gyro bias random walk); 1e-5 gives ~1e-8 relative accuracy.
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-5;
  ceres::GradientChecker checker(&factor, &manifolds, options);
  ceres::GradientChecker::ProbeResults results;
  const auto p = x.pointers();
  // Probe's per-entry verdict flags entries that are zero analytically against ~1e-9 numeric noise; compare
  // each tangent ("local") block relative to its size instead.
  checker.Probe(p.data(), 1e-6, &results);
  ASSERT_EQ(results.local_jacobians.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const Eigen::MatrixXd& numeric = results.local_numeric_jacobians[k];
    EXPECT_LT((results.local_jacobians[k] - numeric).norm(), 1e-7 * numeric.norm()) << "block " << k;
  }
}

TEST(ImuFactor, ReintegratesWhenTheBiasMovesBeyondTheThreshold) {
  const ImuSimulator imu = BiasedImu(200.0);
  const Stamp t_i = kSecond, t_j = 2 * kSecond;
  // Linearized at zero bias; state i carries biases far beyond max_accel_bias_change.
  ImuFactor factor = MakeFactor(imu, t_i, t_j, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  Blocks x = PerturbedBlocks(imu, t_i, t_j, 11, 0.0);
  for (int k = 0; k < 3; ++k) {
    x.speed_bias_i[3 + k] = 3 * kAccelBias[k];
    x.speed_bias_i[6 + k] = 3 * kGyroBias[k];
  }
  const auto p = x.pointers();
  // The same as a factor integrated from scratch at those biases (not a first-order update).
  const ImuFactor fresh = MakeFactor(imu, t_i, t_j, 3 * kAccelBias, 3 * kGyroBias);
  const Vector15d far = factor.Residual(p[0], p[1], p[2], p[3]);
  EXPECT_LT((far - fresh.Residual(p[0], p[1], p[2], p[3])).norm(), 1e-12);
  ExpectJacobiansMatchNumeric(factor, x);
  // Relinearize moves the stored linearization point (and only when beyond the threshold).
  EXPECT_FALSE(factor.Relinearize(Eigen::Vector3d(0.05, 0, 0), Eigen::Vector3d::Zero()));
  EXPECT_TRUE(factor.Relinearize(3 * kAccelBias, 3 * kGyroBias));
  EXPECT_EQ(factor.preintegration().accel_bias(), 3 * kAccelBias);
  EXPECT_LT((factor.Residual(p[0], p[1], p[2], p[3]) - far).norm(), 1e-12);
}

TEST(ImuFactor, PredictedStateGivesZeroResidualAndFiniteJacobians) {
  // State j = Predict(state i): the residual vanishes to rounding, so Log and Jr^-1 are taken at ~0, where
  // their small-angle branches must stay finite.
  const ImuSimulator imu = BiasedImu(200.0);
  const ImuPreintegration pre = Preintegrate(imu, kSecond, kSecond + kSecond / 100, kAccelBias, kGyroBias);
  const NavState state_i = TrueState(imu, kSecond, kAccelBias + Eigen::Vector3d(0.01, 0.0, 0.0), kGyroBias);
  const Blocks x = BlocksOf(state_i, pre.Predict(state_i));
  const ImuFactor factor(pre);
  const auto p = x.pointers();
  EXPECT_LT(factor.Residual(p[0], p[1], p[2], p[3]).norm(), 1e-12);
  Eigen::Matrix<double, 15, 7, Eigen::RowMajor> J0, J2;
  Eigen::Matrix<double, 15, 9, Eigen::RowMajor> J1, J3;
  double* jacobians[4] = {J0.data(), J1.data(), J2.data(), J3.data()};
  Vector15d r;
  ASSERT_TRUE(factor.Evaluate(p.data(), r.data(), jacobians));
  EXPECT_TRUE(r.allFinite() && J0.allFinite() && J1.allFinite() && J2.allFinite() && J3.allFinite());
  EXPECT_LT(r.norm(), 1e-6);
}

// Prior on a pose and a speed_bias block (autodiff; only for the test problem).
struct PosePrior {
  Pose prior;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const Eigen::Quaternion<T> q(pose[6], pose[3], pose[4], pose[5]);
    const Eigen::Quaternion<T> q0 = Eigen::Quaterniond(prior[6], prior[3], prior[4], prior[5]).cast<T>();
    const Eigen::Quaternion<T> dq = q0.conjugate() * q;
    for (int k = 0; k < 3; ++k) {
      residual[k] = 1e3 * (pose[k] - T(prior[k]));
      residual[3 + k] = 2e3 * dq.vec()[k];
    }
    return true;
  }
};
struct SpeedBiasPrior {
  SpeedBias prior;
  template <typename T>
  bool operator()(const T* speed_bias, T* residual) const {
    for (int k = 0; k < 9; ++k) residual[k] = 1e3 * (speed_bias[k] - T(prior[k]));
    return true;
  }
};

TEST(ImuFactor, SmallWindowConvergesToTheTruth) {
  // 5 keyframes 0.5 s apart, noise-free 1 kHz IMU with constant biases, factors linearized at zero bias,
  // a prior on the first state at the truth, noisy initial values for the others.
  const ImuSimulator imu = BiasedImu(1000.0);
  constexpr int kStates = 5;
  std::vector<NavState> truth;
  std::vector<Pose> poses;
  std::vector<SpeedBias> speed_biases;
  std::mt19937_64 random(21);
  std::normal_distribution<double> normal;
  auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * s;
  };
  for (int k = 0; k < kStates; ++k) {
    truth.push_back(TrueState(imu, kSecond / 2 + k * kSecond / 2, kAccelBias, kGyroBias));
    NavState initial = truth.back();
    if (k > 0) {
      initial.T_world_imu =
          SE3(initial.T_world_imu.so3() * SO3::Exp(vec(0.1)), initial.T_world_imu.translation() + vec(0.3));
      initial.velocity += vec(0.3);
      initial.accel_bias = vec(0.02);
      initial.gyro_bias = vec(0.002);
    }
    poses.push_back(PoseBlock(initial.T_world_imu));
    speed_biases.push_back(SpeedBiasBlock(initial));
  }
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  PoseManifold manifold;
  std::vector<std::unique_ptr<ImuFactor>> factors;
  for (int k = 0; k < kStates; ++k) {
    problem.AddParameterBlock(poses[k].data(), kPoseSize, &manifold);
    problem.AddParameterBlock(speed_biases[k].data(), kSpeedBiasSize);
  }
  for (int k = 0; k + 1 < kStates; ++k) {
    factors.push_back(std::make_unique<ImuFactor>(Preintegrate(
        imu, truth[k].stamp, truth[k + 1].stamp, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())));
    problem.AddResidualBlock(factors.back().get(), nullptr, poses[k].data(), speed_biases[k].data(),
                             poses[k + 1].data(), speed_biases[k + 1].data());
  }
  auto* pose_prior =
      new ceres::AutoDiffCostFunction<PosePrior, 6, 7>(new PosePrior{PoseBlock(truth[0].T_world_imu)});
  auto* speed_bias_prior =
      new ceres::AutoDiffCostFunction<SpeedBiasPrior, 9, 9>(new SpeedBiasPrior{SpeedBiasBlock(truth[0])});
  std::unique_ptr<ceres::CostFunction> owned_priors[2] = {
      std::unique_ptr<ceres::CostFunction>(pose_prior),
      std::unique_ptr<ceres::CostFunction>(speed_bias_prior)};
  problem.AddResidualBlock(pose_prior, nullptr, poses[0].data());
  problem.AddResidualBlock(speed_bias_prior, nullptr, speed_biases[0].data());

  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  for (int k = 0; k < kStates; ++k) {
    NavState estimate;
    estimate.T_world_imu = PoseFromBlock(poses[k].data());
    SetSpeedBias(speed_biases[k].data(), estimate);
    EXPECT_LT((truth[k].T_world_imu.so3().inverse() * estimate.T_world_imu.so3()).Log().norm(), 1e-4) << k;
    EXPECT_LT((truth[k].T_world_imu.translation() - estimate.T_world_imu.translation()).norm(), 1e-3) << k;
    EXPECT_LT((truth[k].velocity - estimate.velocity).norm(), 1e-3) << k;
    EXPECT_LT((truth[k].accel_bias - estimate.accel_bias).norm(), 1e-3) << k;
    EXPECT_LT((truth[k].gyro_bias - estimate.gyro_bias).norm(), 1e-4) << k;
  }
}

}  // namespace
}  // namespace uf::estimator
