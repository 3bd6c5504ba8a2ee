// The marginalization prior on a pose chain (the right-multiplicative manifold): at the linearisation point
// the reduced problem keeps the full solution and marginal covariance, away from it the error is close to
// second order, and the prior's Jacobian matches numeric derivatives in the tangent.
#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <random>

#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/window/marginalization.h"
#include "tests/unit/estimator/marginalization_test_support.h"

namespace uf::estimator {
namespace {

using testing::EvaluateDense;
using testing::RowMajorMatrix;

// Relative pose factor r = [R_i^T (t_j - t_i) - t_ij; 2 vec(q_ij^-1 q_i^-1 q_j)] / sigma (autodiff, ambient).
struct RelativePoseResidual {
  Eigen::Vector3d t_ij;
  Eigen::Quaterniond q_ij;
  double sigma;
  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(pose_i), t_j(pose_j);
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(pose_i + 3), q_j(pose_j + 3);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r.template head<3>() = (q_i.conjugate() * (t_j - t_i) - t_ij.cast<T>()) / T(sigma);
    r.template tail<3>() = T(2.0) * (q_ij.cast<T>().conjugate() * q_i.conjugate() * q_j).vec() / T(sigma);
    return true;
  }
};

// Absolute pose factor on one pose (the first pose's prior) and position-only factor (a GNSS-like anchor).
struct AbsolutePoseResidual {
  Eigen::Vector3d t;
  Eigen::Quaterniond q;
  double sigma;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_x(pose + 3);
    for (int i = 0; i < 3; ++i) residual[i] = (pose[i] - T(t[i])) / T(sigma);
    Eigen::Map<Eigen::Matrix<T, 3, 1>>(residual + 3) =
        T(2.0) * (q.cast<T>().conjugate() * q_x).vec() / T(sigma);
    return true;
  }
};
struct PositionResidual {
  Eigen::Vector3d p;
  double sigma;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (pose[i] - T(p[i])) / T(sigma);
    return true;
  }
};

// Four poses on a curve: prior on pose 0, odometry between neighbours, a loop 0-2, a position on pose 3.
struct PoseChain {
  static constexpr int kPoses = 4;
  std::array<std::array<double, 7>, kPoses> pose;
  std::vector<std::unique_ptr<ceres::CostFunction>> factors;
  std::vector<std::vector<int>> factor_poses;
  PoseManifold manifold;

  // noise: standard deviation of the measurement noise (0: consistent measurements, zero residual optimum).
  explicit PoseChain(double noise_sigma = 0.05) {
    std::mt19937_64 random(21);
    std::normal_distribution<double> noise(0.0, noise_sigma);
    const auto noisy = [&] { return Eigen::Vector3d(noise(random), noise(random), noise(random)); };
    std::array<SE3, kPoses> truth;
    for (int k = 0; k < kPoses; ++k) {
      truth[k] = SE3(SO3::Exp(Eigen::Vector3d(0.1 * k, -0.05 * k, 0.4 * k)),
                     Eigen::Vector3d(2.0 * k, std::sin(k), 0.3 * k));
    }
    const auto quat = [](const SO3& R) { return Eigen::Quaterniond(R.matrix()); };
    const auto relative = [&](int i, int j, double sigma) {
      const SE3 T_ij = truth[i].inverse() * truth[j];
      auto* cost = new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 7, 7>(new RelativePoseResidual{
          T_ij.translation() + noisy(), quat(T_ij.so3() * SO3::Exp(noisy())), sigma});
      factors.emplace_back(cost);
      factor_poses.push_back({i, j});
    };
    factors.emplace_back(new ceres::AutoDiffCostFunction<AbsolutePoseResidual, 6, 7>(
        new AbsolutePoseResidual{truth[0].translation(), quat(truth[0].so3()), 0.1}));
    factor_poses.push_back({0});
    for (int k = 0; k + 1 < kPoses; ++k) relative(k, k + 1, 0.05);
    relative(0, 2, 0.1);
    factors.emplace_back(new ceres::AutoDiffCostFunction<PositionResidual, 3, 7>(
        new PositionResidual{truth[3].translation() + noisy(), 0.2}));
    factor_poses.push_back({3});
    for (int k = 0; k < kPoses; ++k) {
      pose[k] = PoseBlock(truth[k]);
      Perturb(k, 0.1, random);
    }
  }
  void Perturb(int k, double size, std::mt19937_64& random) {
    std::normal_distribution<double> normal(0.0, size);
    double delta[6], out[7];
    for (double& d : delta) d = normal(random);
    manifold.Plus(pose[k].data(), delta, out);
    std::copy(out, out + 7, pose[k].data());
  }
  std::vector<double*> Blocks(size_t f) {
    std::vector<double*> blocks;
    for (int k : factor_poses[f]) blocks.push_back(pose[k].data());
    return blocks;
  }
  // Problem with the factors not touching poses < first_kept (plus the prior, if any).
  std::unique_ptr<ceres::Problem> Problem(int first_kept, MarginalizationFactor* prior) {
    ceres::Problem::Options options;
    options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    auto problem = std::make_unique<ceres::Problem>(options);
    for (int k = first_kept; k < kPoses; ++k) problem->AddParameterBlock(pose[k].data(), 7, &manifold);
    if (prior != nullptr) problem->AddResidualBlock(prior, nullptr, prior->prior().ParameterBlocks());
    for (size_t f = 0; f < factors.size(); ++f) {
      if (factor_poses[f].front() >= first_kept)
        problem->AddResidualBlock(factors[f].get(), nullptr, Blocks(f));
    }
    return problem;
  }
  std::vector<double*> Kept(int first_kept) {
    std::vector<double*> blocks;
    for (int k = first_kept; k < kPoses; ++k) blocks.push_back(pose[k].data());
    return blocks;
  }
  std::shared_ptr<MarginalizationPrior> MarginalizeFirst() {
    Marginalizer marginalizer;
    for (auto& p : pose) marginalizer.SetPoseBlock(p.data());
    for (size_t f = 0; f < factors.size(); ++f)
      marginalizer.AddResidualBlock(factors[f].get(), nullptr, Blocks(f));
    marginalizer.MarginalizeBlock(pose[0].data());
    auto prior = marginalizer.Compute();
    EXPECT_TRUE(prior.ok()) << prior.error();
    return prior.value();
  }
};

void SolveTightly(ceres::Problem& problem) {
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
}

// Largest tangent distance between the kept poses and a reference.
double TangentError(PoseChain& chain, const std::array<std::array<double, 7>, PoseChain::kPoses>& reference,
                    int first_kept) {
  double error = 0.0;
  for (int k = first_kept; k < PoseChain::kPoses; ++k) {
    double d[6];
    chain.manifold.Minus(chain.pose[k].data(), reference[k].data(), d);
    for (double v : d) error = std::max(error, std::abs(v));
  }
  return error;
}

TEST(Marginalization, PoseChainAtTheOptimumKeepsSolutionAndCovariance) {
  PoseChain chain;
  auto full = chain.Problem(0, nullptr);
  SolveTightly(*full);
  const auto optimum = chain.pose;
  Eigen::MatrixXd J_full, J_reduced;
  Eigen::VectorXd r;
  EvaluateDense(*full, chain.Kept(0), J_full, r);
  const Eigen::MatrixXd full_covariance = (J_full.transpose() * J_full).inverse().bottomRightCorner(18, 18);

  // Linearised at the optimum, the reduced gradient there is b* + b_other = b_k + b_other = 0 (b_m = 0), so
  // the reduced optimum is the full one, and H* + H_other is the Schur complement of the full H.
  MarginalizationFactor prior(chain.MarginalizeFirst());
  EXPECT_EQ(prior.prior().kept.size(), 2u);  // poses 1 and 2
  auto reduced = chain.Problem(1, &prior);
  EvaluateDense(*reduced, chain.Kept(1), J_reduced, r);
  const Eigen::MatrixXd reduced_covariance = (J_reduced.transpose() * J_reduced).inverse();
  EXPECT_LT((reduced_covariance - full_covariance).norm() / full_covariance.norm(), 1e-9);
  std::mt19937_64 random(4);
  for (int k = 1; k < PoseChain::kPoses; ++k) chain.Perturb(k, 0.05, random);
  SolveTightly(*reduced);
  EXPECT_LT(TangentError(chain, optimum, 1), 1e-8);
}

// Error of the reduced optimum (prior + remaining factors) w.r.t. the full one when the prior is linearised
// at the full optimum moved by `step` (tangent, per coordinate).
double ReducedError(double noise_sigma, double step) {
  PoseChain chain(noise_sigma);
  auto full = chain.Problem(0, nullptr);
  SolveTightly(*full);
  const auto optimum = chain.pose;
  std::mt19937_64 random(8);
  for (int k = 0; k < PoseChain::kPoses; ++k) chain.Perturb(k, step, random);
  MarginalizationFactor prior(chain.MarginalizeFirst());
  auto reduced = chain.Problem(1, &prior);
  SolveTightly(*reduced);
  return TangentError(chain, optimum, 1);
}

// Away from the optimum the prior is a Gauss-Newton linearisation of the marginalized residuals: with
// consistent measurements (zero residual at the optimum) the GN Hessian is exact there, so the reduced
// optimum's error is second order in the linearisation offset d (halving d divides it by ~4). With noisy
// measurements the GN Hessian misses sum r_i Hess(r_i) (residuals ~ 1 sigma here), a first-order error
// that is a fraction of d: bounded by d / 2.
TEST(Marginalization, PoseChainAwayFromTheOptimumIsCloseToSecondOrder) {
  const double consistent_coarse = ReducedError(0.0, 2e-3), consistent_fine = ReducedError(0.0, 1e-3);
  EXPECT_LT(consistent_fine, 1e-5);
  EXPECT_GT(consistent_coarse / consistent_fine, 3.0);
  const double noisy = ReducedError(0.05, 1e-3);
  EXPECT_LT(noisy, 0.5e-3);
  std::printf("reduced-optimum error: consistent %.3g (d=2e-3) %.3g (d=1e-3), noisy %.3g (d=1e-3)\n",
              consistent_coarse, consistent_fine, noisy);
}

TEST(Marginalization, PriorJacobianMatchesNumericDerivativesInTheTangent) {
  PoseChain chain;
  MarginalizationFactor factor(chain.MarginalizeFirst());
  const MarginalizationPrior& prior = factor.prior();
  const std::vector<double*> blocks = prior.ParameterBlocks();
  const int rows = prior.Rank();
  // At x0 the residual is r0.
  Eigen::VectorXd r(rows);
  ASSERT_TRUE(factor.Evaluate(blocks.data(), r.data(), nullptr));
  EXPECT_LT((r - prior.r0).norm(), 1e-12);
  // Away from x0 (0.3 rad, 0.3 m scale), ambient Jacobian x PlusJacobian against central differences.
  std::mt19937_64 random(13);
  chain.Perturb(1, 0.3, random);
  chain.Perturb(2, 0.3, random);
  std::vector<RowMajorMatrix> ambient(blocks.size(), RowMajorMatrix(rows, 7));
  std::vector<double*> jacobians = {ambient[0].data(), ambient[1].data()};
  ASSERT_TRUE(factor.Evaluate(blocks.data(), r.data(), jacobians.data()));
  const double h = 1e-6;
  for (size_t b = 0; b < blocks.size(); ++b) {
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
    chain.manifold.PlusJacobian(blocks[b], plus.data());
    const Eigen::MatrixXd analytic = ambient[b] * plus;
    const std::array<double, 7> x = {blocks[b][0], blocks[b][1], blocks[b][2], blocks[b][3],
                                     blocks[b][4], blocks[b][5], blocks[b][6]};
    for (int k = 0; k < 6; ++k) {
      Eigen::VectorXd forward(rows), backward(rows);
      double delta[6] = {0, 0, 0, 0, 0, 0};
      delta[k] = h;
      chain.manifold.Plus(x.data(), delta, blocks[b]);
      factor.Evaluate(blocks.data(), forward.data(), nullptr);
      delta[k] = -h;
      chain.manifold.Plus(x.data(), delta, blocks[b]);
      factor.Evaluate(blocks.data(), backward.data(), nullptr);
      std::copy(x.begin(), x.end(), blocks[b]);
      const Eigen::VectorXd numeric = (forward - backward) / (2 * h);
      EXPECT_LT((analytic.col(k) - numeric).norm(), 1e-6 * (1.0 + numeric.norm()))
          << "block " << b << " dir " << k;
    }
  }
}

}  // namespace
}  // namespace uf::estimator
