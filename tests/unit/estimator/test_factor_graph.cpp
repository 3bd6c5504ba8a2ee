// The generic factor graph of the window against independent truth: on a linear-Gaussian chain whose
// factors are of every kind (absolute "GNSS" and "LiDAR" anchors, relative "wheel" and "IMU" links, a
// three-state "motion prior"), solving after marginalizing the oldest states gives the closed-form full
// solution of the kept states (checked by an exact Gauss-Newton step, then by the dense and the Ceres solve);
// the marginalization rules (no prior from motion factors alone; entries and blocks leave with the states)
// and the solve's factor filter.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/estimator/window/factor_graph.h"
#include "tests/unit/estimator/marginalization_test_support.h"

namespace uf::estimator {
namespace {

using testing::LinearFactor;

constexpr int kStates = 6;

struct ChainFactor {
  FactorKind kind;
  std::vector<int> states;
  std::vector<Eigen::MatrixXd> A;
  Eigen::VectorXd z;
  double sigma;
  bool anchors;
};

// States x0..x5 (3-D), factors of mixed kinds; the values start far from the solution.
struct MixedChain {
  std::array<Eigen::Vector3d, kStates> x;
  std::vector<ChainFactor> factors;

  MixedChain() {
    std::mt19937_64 random(7);
    std::normal_distribution<double> normal;
    const auto vec = [&] { return Eigen::Vector3d(normal(random), normal(random), normal(random)); };
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    factors.push_back({FactorKind::kGnss, {0}, {I}, vec(), 0.5, true});
    for (int i = 0; i + 1 < kStates; ++i)
      factors.push_back({FactorKind::kWheel, {i, i + 1}, {-I, I}, vec(), 0.2, false});
    for (int i = 0; i + 2 < kStates; ++i)  // second difference x_i - 2 x_{i+1} + x_{i+2}
      factors.push_back({FactorKind::kMotionPrior, {i, i + 1, i + 2}, {I, -2 * I, I}, vec(), 0.4, false});
    Eigen::Matrix3d mixed;
    mixed << 1, 0.3, 0, -0.2, 1, 0.1, 0, 0.4, 1;
    factors.push_back({FactorKind::kImu, {0, 2}, {-mixed, mixed}, vec(), 0.3, false});
    factors.push_back({FactorKind::kLidar, {3}, {I}, vec(), 1.0, true});
    factors.push_back({FactorKind::kLidar, {5}, {I}, vec(), 1.0, true});
    for (auto& state : x) state = 3.0 * vec();
  }

  // Closed form: H = sum A^T A / sigma^2, x = H^-1 sum A^T z / sigma^2, over all factors.
  Eigen::VectorXd FullSolution() const {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * kStates, 3 * kStates);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * kStates);
    for (const ChainFactor& f : factors) {
      const double w = 1.0 / (f.sigma * f.sigma);
      for (size_t i = 0; i < f.states.size(); ++i) {
        g.segment<3>(3 * f.states[i]) += w * f.A[i].transpose() * f.z;
        for (size_t j = 0; j < f.states.size(); ++j)
          H.block<3, 3>(3 * f.states[i], 3 * f.states[j]) += w * f.A[i].transpose() * f.A[j];
      }
    }
    return H.ldlt().solve(g);
  }

  void AddTo(FactorGraph& graph) {
    for (auto& state : x) graph.AddEuclideanBlock(state.data(), 3);
    for (const ChainFactor& f : factors) {
      std::vector<double*> blocks;
      for (int s : f.states) blocks.push_back(x[s].data());
      graph.Add(f.kind, f.states.back(), std::make_unique<LinearFactor>(f.A, f.z, f.sigma), nullptr, blocks,
                f.anchors);
    }
  }

  WindowSolveRequest FreeFrom(int first, WindowSolver solver) {
    WindowSolveRequest request;
    for (int s = first; s < kStates; ++s) request.free.push_back(x[s].data());
    request.solver = solver;
    request.max_iterations = 20;
    request.max_time_s = 10;
    return request;
  }

  double MaxErrorFrom(int first, const Eigen::VectorXd& truth) const {
    double worst = 0;
    for (int s = first; s < kStates; ++s)
      worst = std::max(worst, (x[s] - truth.segment<3>(3 * s)).cwiseAbs().maxCoeff());
    return worst;
  }
};

// The kept states after one Gauss-Newton step on the graph's remaining entries and prior from the current
// values: exact for a linear problem, so this checks the prior itself, not a solver's stopping rule.
Eigen::VectorXd GaussNewtonKept(MixedChain& chain, const FactorGraph& graph, int first) {
  DenseLeastSquares system;
  for (int s = first; s < kStates; ++s) system.AddEuclideanBlock(chain.x[s].data(), 3);
  for (int k = 0; k < kFactorKinds; ++k)
    for (const Factor& f : graph.Entries(static_cast<FactorKind>(k)))
      system.AddResidualBlock(f.cost.get(), f.loss.get(), f.blocks);
  system.AddResidualBlock(graph.prior(), nullptr, graph.prior()->prior().ParameterBlocks());
  double cost = 0;
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  EXPECT_TRUE(system.Linearize(&cost, &H, &g));
  Eigen::VectorXd x(3 * (kStates - first));
  for (int s = first; s < kStates; ++s) x.segment<3>(3 * (s - first)) = chain.x[s];
  return x - H.ldlt().solve(g);
}

TEST(FactorGraph, MarginalizingMixedKindsKeepsTheFullSolution) {
  MixedChain chain;
  const Eigen::VectorXd truth = chain.FullSolution();
  FactorGraph graph;
  chain.AddTo(graph);
  // Step 1: x0 leaves (a linear problem's prior does not depend on the linearisation point).
  ASSERT_TRUE(graph.Marginalize({chain.x[0].data()}, {}).ok());
  ASSERT_NE(graph.prior(), nullptr);
  EXPECT_EQ(graph.Entries(FactorKind::kGnss).size(), 0u);  // its only factor touched x0
  EXPECT_LT((GaussNewtonKept(chain, graph, 1) - truth.tail(3 * (kStates - 1))).cwiseAbs().maxCoeff(), 1e-9);
  // Step 2: at another linearisation point x1 leaves; the previous prior is folded like any factor.
  chain.x[1] += Eigen::Vector3d(0.7, -1.1, 0.4);
  chain.x[2] -= Eigen::Vector3d(0.2, 0.5, -0.9);
  ASSERT_TRUE(graph.Marginalize({chain.x[1].data()}, {}).ok());
  EXPECT_LT((GaussNewtonKept(chain, graph, 2) - truth.tail(3 * (kStates - 2))).cwiseAbs().maxCoeff(), 1e-9);
}

// Both solvers reach the full solution from start values metres away, up to their stopping rule (a relative
// cost decrease below 1e-6 ends the iterations; 1 cm is far above what that leaves and far below the start
// error).
class FactorGraphSolvers : public ::testing::TestWithParam<WindowSolver> {};

TEST_P(FactorGraphSolvers, SolveAfterMarginalizationReachesTheFullSolution) {
  MixedChain chain;
  const Eigen::VectorXd truth = chain.FullSolution();
  ASSERT_GT(chain.MaxErrorFrom(1, truth), 1.0);
  FactorGraph graph;
  chain.AddTo(graph);
  ASSERT_TRUE(graph.Marginalize({chain.x[0].data()}, {}).ok());
  ASSERT_TRUE(graph.Solve(chain.FreeFrom(1, GetParam())).usable);
  EXPECT_LT(chain.MaxErrorFrom(1, truth), 0.01);
}

INSTANTIATE_TEST_SUITE_P(DenseAndCeres, FactorGraphSolvers,
                         ::testing::Values(WindowSolver::kDense, WindowSolver::kCeres));

// Condensed entries (window/condensed_factor.h) are their own Gauss-Newton model, exact for linear factors:
// one round reaches the full solution as the plain solve does.
TEST(FactorGraph, CondensedEntriesOfALinearChainGiveTheFullSolution) {
  MixedChain chain;
  const Eigen::VectorXd truth = chain.FullSolution();
  FactorGraph graph;
  chain.AddTo(graph);
  ASSERT_TRUE(graph.Marginalize({chain.x[0].data()}, {}).ok());
  WindowSolveRequest request = chain.FreeFrom(1, WindowSolver::kDense);
  request.condense = [](const Factor& f) {
    return f.kind == FactorKind::kLidar || f.kind == FactorKind::kWheel;
  };
  request.condensed_rounds = 1;
  ASSERT_TRUE(graph.Solve(request).usable);
  EXPECT_LT(chain.MaxErrorFrom(1, truth), 0.01);
  EXPECT_EQ(graph.Entries(FactorKind::kWheel).size(), static_cast<size_t>(kStates - 2));  // the entries stay
}

TEST(FactorGraph, MotionFactorsAloneMakeNoPrior) {
  MixedChain chain;
  chain.factors.erase(std::remove_if(chain.factors.begin(), chain.factors.end(),
                                     [](const ChainFactor& f) { return f.anchors; }),
                      chain.factors.end());
  FactorGraph graph;
  chain.AddTo(graph);
  ASSERT_TRUE(graph.Marginalize({chain.x[0].data()}, {}).ok());
  EXPECT_EQ(graph.prior(), nullptr);
  // The entries on x0 are gone with it: one wheel link, one second difference, the x0-x2 link.
  EXPECT_EQ(graph.Entries(FactorKind::kWheel).size(), static_cast<size_t>(kStates - 2));
  EXPECT_EQ(graph.Entries(FactorKind::kMotionPrior).size(), static_cast<size_t>(kStates - 3));
  EXPECT_EQ(graph.Entries(FactorKind::kImu).size(), 0u);
  EXPECT_FALSE(graph.IsPoseBlock(chain.x[0].data()));
}

TEST(FactorGraph, SolveUsesOnlyTheFilteredEntriesTouchingFreeBlocks) {
  MixedChain chain;
  FactorGraph graph;
  chain.AddTo(graph);
  // Only x5 free, only the LiDAR entries: the absolute factor on x5 alone pins it to its measurement (up to
  // the stopping rule, from ~3 m away).
  WindowSolveRequest request = chain.FreeFrom(5, WindowSolver::kDense);
  request.use = [](const Factor& f) { return f.kind == FactorKind::kLidar; };
  const Eigen::Vector3d x3 = chain.x[3];
  ASSERT_TRUE(graph.Solve(request).usable);
  EXPECT_LT((chain.x[5] - chain.factors.back().z).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(chain.x[3], x3);  // constant
  EXPECT_EQ(graph.Count(FactorKind::kLidar, 5), 1);
  graph.Remove(FactorKind::kLidar, 5);
  EXPECT_EQ(graph.Count(FactorKind::kLidar, 5), 0);
  EXPECT_STREQ(FactorKindName(FactorKind::kWheel), "wheel");
}

}  // namespace
}  // namespace uf::estimator
