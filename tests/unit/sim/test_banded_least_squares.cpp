#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "odometry/sim/banded_least_squares.h"

namespace uf::spline {
namespace {

// A random banded problem solved both ways: the banded accumulation and a dense least-squares solve of the
// stacked rows must agree.
TEST(BandedLeastSquaresTest, MatchesDenseSolveOfStackedRows) {
  constexpr int kBlocks = 9, kBlockSize = 2, kColumns = 3;
  std::mt19937 engine(7);
  std::normal_distribution<double> normal;
  const auto random = [&](int rows, int cols) {
    Eigen::MatrixXd m(rows, cols);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) m(r, c) = normal(engine);
    }
    return m;
  };
  BandedLeastSquares problem(kBlocks, kBlockSize, kColumns);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(0, kBlocks * kBlockSize), Y(0, kColumns);
  for (int residual = 0; residual < 30; ++residual) {
    const int span = 1 + residual % 4;
    const int first = (residual * 5) % (kBlocks - span + 1);
    const double weight = 0.5 + residual % 3;
    const Eigen::MatrixXd J = random(3, span * kBlockSize), y = random(3, kColumns);
    problem.Add(first, J, y, weight);
    A.conservativeResize(A.rows() + 3, Eigen::NoChange);
    Y.conservativeResize(Y.rows() + 3, Eigen::NoChange);
    A.bottomRows(3).setZero();
    A.bottomRows(3).middleCols(first * kBlockSize, span * kBlockSize) = std::sqrt(weight) * J;
    Y.bottomRows(3) = std::sqrt(weight) * y;
  }
  const Expected<Eigen::MatrixXd> banded = problem.Solve();
  ASSERT_TRUE(banded.ok()) << banded.error();
  const Eigen::MatrixXd dense = A.colPivHouseholderQr().solve(Y);
  EXPECT_LT((*banded - dense).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(BandedLeastSquaresTest, UnconstrainedUnknownIsAnError) {
  BandedLeastSquares problem(3, 1, 1);
  problem.Add(0, Eigen::RowVector2d(1.0, 0.0), Eigen::MatrixXd::Ones(1, 1));
  problem.Add(0, Eigen::RowVector2d(0.0, 1.0), Eigen::MatrixXd::Ones(1, 1));
  const Expected<Eigen::MatrixXd> solution = problem.Solve();  // block 2 appears in no residual
  ASSERT_FALSE(solution.ok());
  EXPECT_NE(solution.error().find("singular"), std::string::npos) << solution.error();
}

}  // namespace
}  // namespace uf::spline
