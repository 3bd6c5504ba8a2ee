// The marginalization prior against independent truth: on a linear-Gaussian chain the reduced problem
// (prior + remaining factors) gives the full problem's estimate and marginal covariance (closed-form normal
// equations), also after a second marginalization of the prior itself; robust reweighting and eigenvalue
// truncation against hand-computed values; bad input. The pose-chain cases are in
// test_marginalization_poses.cpp.
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
using testing::LinearFactor;
using testing::RowMajorMatrix;

// One linear 3-D chain: states x0..x4, a prior on x0, relative measurements, absolute ones on x2, x4 and a
// loop x0-x2 (so marginalizing x0 creates fill-in between x1 and x2).
struct LinearChain {
  static constexpr int kStates = 5;
  std::array<Eigen::Vector3d, kStates> x;
  std::vector<std::unique_ptr<LinearFactor>> factors;
  std::vector<std::vector<int>> factor_states;

  LinearChain() {
    std::mt19937_64 random(11);
    std::normal_distribution<double> normal;
    const auto vec = [&] { return Eigen::Vector3d(normal(random), normal(random), normal(random)); };
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    Add({0}, {I}, vec(), 0.5);
    for (int i = 0; i + 1 < kStates; ++i) Add({i, i + 1}, {-I, I}, vec(), 0.2);
    Add({2}, {I}, vec(), 1.0);
    Add({4}, {I}, vec(), 1.0);
    Eigen::Matrix3d mixed;  // a non-diagonal loop closure
    mixed << 1, 0.3, 0, -0.2, 1, 0.1, 0, 0.4, 1;
    Add({0, 2}, {-mixed, mixed}, vec(), 0.3);
    for (auto& state : x) state = 3.0 * vec();  // linearisation point far from the solution
  }
  void Add(std::vector<int> states, std::vector<Eigen::MatrixXd> A, Eigen::VectorXd z, double sigma) {
    factors.push_back(std::make_unique<LinearFactor>(std::move(A), std::move(z), sigma));
    factor_states.push_back(std::move(states));
  }
  std::vector<double*> Blocks(int i) {
    std::vector<double*> blocks;
    for (int s : factor_states[i]) blocks.push_back(x[s].data());
    return blocks;
  }
  // Closed-form full solution: H = sum A^T A / sigma^2, x = H^-1 sum A^T z / sigma^2.
  void Solve(Eigen::VectorXd& mean, Eigen::MatrixXd& covariance) const {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * kStates, 3 * kStates);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * kStates);
    for (size_t f = 0; f < factors.size(); ++f) {
      const LinearFactor& factor = *factors[f];
      const double w = 1.0 / (factor.sigma_ * factor.sigma_);
      for (size_t i = 0; i < factor_states[f].size(); ++i) {
        g.segment<3>(3 * factor_states[f][i]) += w * factor.A_[i].transpose() * factor.z_;
        for (size_t j = 0; j < factor_states[f].size(); ++j) {
          H.block<3, 3>(3 * factor_states[f][i], 3 * factor_states[f][j]) +=
              w * factor.A_[i].transpose() * factor.A_[j];
        }
      }
    }
    covariance = H.inverse();
    mean = covariance * g;
  }
};

// Reduced problem: the prior plus the factors not touching states < first_kept. Solved by one Gauss-Newton
// step (exact for a linear problem); returns the kept states' estimate and covariance (J^T J)^-1.
void SolveReduced(LinearChain& chain, MarginalizationFactor& prior, int first_kept, Eigen::VectorXd& mean,
                  Eigen::MatrixXd& covariance) {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(options);
  problem.AddResidualBlock(&prior, nullptr, prior.prior().ParameterBlocks());
  for (size_t f = 0; f < chain.factors.size(); ++f) {
    const auto& states = chain.factor_states[f];
    if (*std::min_element(states.begin(), states.end()) >= first_kept) {
      problem.AddResidualBlock(chain.factors[f].get(), nullptr, chain.Blocks(static_cast<int>(f)));
    }
  }
  std::vector<double*> blocks;
  for (int s = first_kept; s < LinearChain::kStates; ++s) blocks.push_back(chain.x[s].data());
  Eigen::MatrixXd J;
  Eigen::VectorXd r;
  EvaluateDense(problem, blocks, J, r);
  covariance = (J.transpose() * J).inverse();
  mean.resize(J.cols());
  for (int s = first_kept; s < LinearChain::kStates; ++s) mean.segment<3>(3 * (s - first_kept)) = chain.x[s];
  mean -= covariance * J.transpose() * r;
}

TEST(Marginalization, LinearChainMatchesFullSolutionOverTwoSteps) {
  LinearChain chain;
  Eigen::VectorXd full_mean;
  Eigen::MatrixXd full_covariance;
  chain.Solve(full_mean, full_covariance);

  // Step 1: marginalize x0 (all factors offered; the marginalizer picks those touching x0).
  Marginalizer first;
  for (size_t f = 0; f < chain.factors.size(); ++f) {
    first.AddResidualBlock(chain.factors[f].get(), nullptr, chain.Blocks(static_cast<int>(f)));
  }
  first.MarginalizeBlock(chain.x[0].data());
  auto prior1 = first.Compute();
  ASSERT_TRUE(prior1.ok()) << prior1.error();
  ASSERT_EQ(prior1.value()->kept.size(), 2u);  // x1 (relative) and x2 (loop)
  EXPECT_EQ(prior1.value()->Rank(), 6);
  MarginalizationFactor factor1(prior1.value());
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;
  SolveReduced(chain, factor1, 1, mean, covariance);
  EXPECT_LT((mean - full_mean.tail(12)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((covariance - full_covariance.bottomRightCorner(12, 12)).cwiseAbs().maxCoeff(), 1e-9);

  // Step 2: at another linearisation point, marginalize x1: the previous prior takes part like any factor.
  chain.x[1] += Eigen::Vector3d(0.7, -1.1, 0.4);
  chain.x[2] -= Eigen::Vector3d(0.2, 0.5, -0.9);
  Marginalizer second;
  second.AddPrior(&factor1);
  for (size_t f = 0; f < chain.factors.size(); ++f) {
    const auto& states = chain.factor_states[f];
    if (states.front() >= 1) second.AddResidualBlock(chain.factors[f].get(), nullptr, chain.Blocks(f));
  }
  second.MarginalizeBlock(chain.x[1].data());
  auto prior2 = second.Compute();
  ASSERT_TRUE(prior2.ok()) << prior2.error();
  ASSERT_EQ(prior2.value()->kept.size(), 1u);  // only x2 remains connected
  MarginalizationFactor factor2(prior2.value());
  SolveReduced(chain, factor2, 2, mean, covariance);
  EXPECT_LT((mean - full_mean.tail(9)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((covariance - full_covariance.bottomRightCorner(9, 9)).cwiseAbs().maxCoeff(), 1e-9);
}

// 1-D blocks m and k: r1 = x_m (sigma 1), r2 = x_k - x_m with Huber(1), linearised at x_m = 0, x_k = 4.
// Huber beyond 1: rho(s) = 2 sqrt(s) - 1, rho' = 1/sqrt(s) = 1/4, rho'' < 0 -> plain sqrt(rho') scaling:
// J2 = 1/2 [-1, 1], r2 = 2. H = [[1.25, -0.25], [-0.25, 0.25]], b = [1, -1];
// H* = 0.25 - 0.0625 / 1.25 = 0.2, b* = -1 - (-0.25)(1 / 1.25)(1) = -0.8.
TEST(Marginalization, RobustLossReweightsLikeCeres) {
  double x_m = 0.0, x_k = 4.0;
  LinearFactor f1({Eigen::MatrixXd::Ones(1, 1)}, Eigen::VectorXd::Zero(1), 1.0);
  LinearFactor f2({-Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1)}, Eigen::VectorXd::Zero(1), 1.0);
  ceres::HuberLoss huber(1.0);
  Marginalizer marginalizer;
  marginalizer.AddResidualBlock(&f1, nullptr, {&x_m});
  marginalizer.AddResidualBlock(&f2, &huber, {&x_m, &x_k});
  marginalizer.MarginalizeBlock(&x_m);
  auto prior = marginalizer.Compute();
  ASSERT_TRUE(prior.ok()) << prior.error();
  ASSERT_EQ(prior.value()->Rank(), 1);
  const double J = prior.value()->J(0, 0), r0 = prior.value()->r0[0];
  EXPECT_NEAR(J * J, 0.2, 1e-12);   // H*
  EXPECT_NEAR(J * r0, 0.8, 1e-12);  // -b*
}

// A marginalized 3-D state observed only along x: H_mm has two zero eigenvalues (and a third direction with
// information 1e-14, below the 1e-8 threshold). r1 = x_m.x - 1, r2 = (x_k - x_m).x - 2 (sigma 1):
// along x, H = [[2, -1], [-1, 1]], b = [-1, 2] at 0 -> H* = 1/2, b* = 3/2 (x_k.x = 3, hand-solved);
// the prior must be finite, of rank 1, and act only along x_k.x.
TEST(Marginalization, RankDeficientMarginalizedStateIsTruncated) {
  Eigen::Vector3d x_m = Eigen::Vector3d::Zero(), x_k = Eigen::Vector3d::Zero();
  const Eigen::MatrixXd ex = Eigen::RowVector3d(1, 0, 0);
  const Eigen::MatrixXd ey_tiny = Eigen::RowVector3d(0, 1e-7, 0);  // information 1e-14 along y
  LinearFactor f1({ex}, Eigen::VectorXd::Ones(1), 1.0);
  LinearFactor f2({-ex, ex}, 2.0 * Eigen::VectorXd::Ones(1), 1.0);
  LinearFactor f3({ey_tiny}, Eigen::VectorXd::Ones(1), 1.0);
  Marginalizer marginalizer;
  marginalizer.AddResidualBlock(&f1, nullptr, {x_m.data()});
  marginalizer.AddResidualBlock(&f2, nullptr, {x_m.data(), x_k.data()});
  marginalizer.AddResidualBlock(&f3, nullptr, {x_m.data()});
  marginalizer.MarginalizeBlock(x_m.data());
  auto prior = marginalizer.Compute();
  ASSERT_TRUE(prior.ok()) << prior.error();
  ASSERT_EQ(prior.value()->Rank(), 1);
  const Eigen::MatrixXd& J = prior.value()->J;
  EXPECT_TRUE(J.allFinite() && prior.value()->r0.allFinite());
  const Eigen::Matrix3d H = J.transpose() * J;
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  expected(0, 0) = 0.5;
  EXPECT_LT((H - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR((J.transpose() * prior.value()->r0)[0], -1.5, 1e-12);
}

TEST(Marginalization, ReportsBadInput) {
  MarginalizationConfig config;
  config.eigenvalue_threshold = -1.0;
  EXPECT_NE(config.Validate().message().find("marginalization.eigenvalue_threshold"), std::string::npos);
  double a = 0.0, b = 0.0;
  LinearFactor f({Eigen::MatrixXd::Ones(1, 1)}, Eigen::VectorXd::Zero(1), 1.0);
  Marginalizer untouched;
  untouched.AddResidualBlock(&f, nullptr, {&a});
  untouched.MarginalizeBlock(&b);
  EXPECT_FALSE(untouched.Compute().ok());
  Marginalizer nothing_kept;
  nothing_kept.AddResidualBlock(&f, nullptr, {&a});
  nothing_kept.MarginalizeBlock(&a);
  EXPECT_FALSE(nothing_kept.Compute().ok());
  Marginalizer bad_config(config);
  EXPECT_FALSE(bad_config.Compute().ok());
}

}  // namespace
}  // namespace uf::estimator
