// The marginalization prior against independent truth: on a linear-Gaussian chain the reduced problem
// (prior + remaining factors) gives the full problem's estimate and marginal covariance (closed-form normal
// equations), also after a second marginalization of the prior itself; on a pose chain the same holds at the
// linearisation point and to second order away from it, and the prior's Jacobian matches numeric derivatives
// in the tangent; robust reweighting and eigenvalue truncation against hand-computed values.
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

namespace uf::estimator {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// r = (sum_i A_i x_i - z) / sigma on Euclidean blocks.
class LinearFactor : public ceres::CostFunction {
 public:
  LinearFactor(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd z, double sigma)
      : A_(std::move(A)), z_(std::move(z)), sigma_(sigma) {
    set_num_residuals(static_cast<int>(z_.size()));
    for (const auto& a : A_) mutable_parameter_block_sizes()->push_back(static_cast<int>(a.cols()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::VectorXd r = -z_;
    for (size_t i = 0; i < A_.size(); ++i) r += A_[i] * Eigen::Map<const Eigen::VectorXd>(x[i], A_[i].cols());
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r / sigma_;
    for (size_t i = 0; jacobians != nullptr && i < A_.size(); ++i) {
      if (jacobians[i]) Eigen::Map<RowMajorMatrix>(jacobians[i], A_[i].rows(), A_[i].cols()) = A_[i] / sigma_;
    }
    return true;
  }
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd z_;
  double sigma_;
};

// Dense tangent Jacobian and residual of a problem over the given blocks (Problem::Evaluate uses tangents).
void EvaluateDense(ceres::Problem& problem, const std::vector<double*>& blocks, Eigen::MatrixXd& J,
                   Eigen::VectorXd& r) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  problem.Evaluate(options, nullptr, &residuals, nullptr, &crs);
  J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) J(row, crs.cols[k]) = crs.values[k];
  }
  r = Eigen::Map<Eigen::VectorXd>(residuals.data(), residuals.size());
}

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
