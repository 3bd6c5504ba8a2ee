// DenseLeastSquares (window/dense_least_squares.h) against independent truth: on a linear problem one
// Gauss-Newton step lands on the closed-form least-squares solution; its normal equations equal J^T J and
// J^T r from Ceres' own Jacobian (ceres::Problem::Evaluate) with robust loss and constant blocks, and do not
// depend on the number of threads; and on a
// deskewed point-to-plane registration of two poses with a constant-velocity prior (the LiDAR window's
// problem) it reaches the same solution as ceres::Solve, which is the true motion.
#include <ceres/ceres.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <Eigen/Dense>
#include <memory>
#include <random>
#include <tuple>

#include "odometry/estimator/factors/constant_velocity_factor.h"
#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/lidar_odometry/sweep_poses.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/window/dense_least_squares.h"

namespace uf::estimator {
namespace {

// r = A x - b on one Euclidean block of size 3.
class LinearCost : public ceres::SizedCostFunction<4, 3> {
 public:
  LinearCost(const Eigen::Matrix<double, 4, 3>& A, const Eigen::Vector4d& b) : A_(A), b_(b) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::Vector3d> x(parameters[0]);
    Eigen::Map<Eigen::Vector4d> r(residuals);
    r = A_ * x - b_;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>> J(jacobians[0]);
      J = A_;
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 4, 3> A_;
  Eigen::Vector4d b_;
};

TEST(DenseLeastSquares, LinearProblemReachesTheNormalEquationsSolution) {
  Eigen::Matrix<double, 4, 3> A;
  A << 2, 0, 1, -1, 3, 0, 0.5, 1, 4, 1, -2, 1;
  const Eigen::Vector4d b(1, -2, 3, 0.5);
  const LinearCost cost(A, b);
  double x[3] = {10, -7, 3};
  DenseLeastSquares problem;
  problem.AddEuclideanBlock(x, 3);
  problem.AddResidualBlock(&cost, nullptr, {x});
  const DenseSolverSummary summary = problem.Solve({});
  ASSERT_TRUE(summary.usable);
  const Eigen::Vector3d expected = (A.transpose() * A).ldlt().solve(A.transpose() * b);
  EXPECT_NEAR((Eigen::Map<Eigen::Vector3d>(x) - expected).norm(), 0, 1e-6);
  EXPECT_NEAR(summary.final_cost, 0.5 * (A * expected - b).squaredNorm(), 1e-9);
}

// Planes around the origin (a room-like set of normals) and a scan of points on them, measured during a
// sweep from T_begin to T_end (point i at fraction alpha_i), expressed in the lidar frame at its own time.
struct SweepScan {
  std::vector<std::unique_ptr<PointToPlaneFactor>> factors;
  std::unique_ptr<ceres::LossFunction> loss = std::make_unique<ceres::HuberLoss>(0.5 / 0.05);
};

SweepScan MakeScan(const SE3& T_begin, const SE3& T_end, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const Eigen::Vector3d normals[5] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
                                      Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY(),
                                      Eigen::Vector3d::UnitZ()};
  const double offsets[5] = {6, 7, 5, 8, 1.8};  // plane n^T x = -offset (walls and the floor below)
  SweepScan scan;
  for (int i = 0; i < count; ++i) {
    const int k = i % 5;
    const double alpha = (i + 0.5) / count;
    // A point on plane k: n^T q = -offset.
    Eigen::Vector3d q(uniform(rng) * 5, uniform(rng) * 5, uniform(rng) * 2);
    q -= (normals[k].dot(q) + offsets[k]) * normals[k];
    const Plane plane{normals[k], -offsets[k] * normals[k], 0.05};
    const SE3 T_world_lidar = PoseAt(T_begin, T_end, alpha);
    scan.factors.push_back(
        std::make_unique<PointToPlaneFactor>(T_world_lidar.inverse() * q, alpha, plane, SE3()));
  }
  return scan;
}

// The normal equations of `points` point-to-plane residuals and a constant-velocity prior against Ceres'
// Jacobian; enough points split the residual blocks into several chunks evaluated on different threads.
void ExpectNormalEquationsOfCeres(int points) {
  const SE3 T_begin(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(1, 2, 0.1));
  const SE3 T_end(SO3::Exp(Eigen::Vector3d(0.02, 0.0, 0.38)), Eigen::Vector3d(2, 2.4, 0.1));
  const SweepScan scan = MakeScan(T_begin, T_end, points, 7);
  // Evaluate away from the truth so that the Huber loss is active on some residuals.
  auto begin = PoseBlock(T_begin * SE3::Exp((Vector6d() << 0.3, -0.2, 0.1, 0.02, 0.01, -0.03).finished()));
  auto end = PoseBlock(T_end * SE3::Exp((Vector6d() << -0.1, 0.2, 0.05, -0.01, 0.02, 0.01).finished()));
  auto fixed = PoseBlock(SE3(SO3(), Eigen::Vector3d(-1, 1.5, 0.1)));
  const auto prior = MakeConstantVelocityFactor(0.05, 0.1, {});

  DenseLeastSquares dense;
  dense.AddPoseBlock(begin.data());
  dense.AddPoseBlock(end.data());
  PoseManifold manifold;
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(options);
  for (double* block : {begin.data(), end.data(), fixed.data()})
    ceres_problem.AddParameterBlock(block, 7, &manifold);
  ceres_problem.SetParameterBlockConstant(fixed.data());
  for (const auto& factor : scan.factors) {
    dense.AddResidualBlock(factor.get(), scan.loss.get(), {begin.data(), end.data()});
    ceres_problem.AddResidualBlock(factor.get(), scan.loss.get(), begin.data(), end.data());
  }
  dense.AddResidualBlock(prior.get(), nullptr, {fixed.data(), begin.data(), end.data()});
  ceres_problem.AddResidualBlock(prior.get(), nullptr, fixed.data(), begin.data(), end.data());

  double cost = 0;
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  ASSERT_TRUE(dense.Linearize(&cost, &H, &g));
  if (::testing::Test::HasFatalFailure()) return;
  double ceres_cost = 0;
  std::vector<double> residuals;
  ceres::CRSMatrix jacobian;
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = {begin.data(), end.data()};
  ASSERT_TRUE(ceres_problem.Evaluate(evaluate, &ceres_cost, &residuals, nullptr, &jacobian));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jacobian.num_rows, jacobian.num_cols);
  for (int row = 0; row < jacobian.num_rows; ++row)
    for (int at = jacobian.rows[row]; at < jacobian.rows[row + 1]; ++at)
      J(row, jacobian.cols[at]) = jacobian.values[at];
  const Eigen::VectorXd r = Eigen::Map<Eigen::VectorXd>(residuals.data(), residuals.size());
  ASSERT_EQ(J.cols(), 12);
  EXPECT_NEAR(cost, ceres_cost, 1e-9 * ceres_cost);
  EXPECT_LT((H - J.transpose() * J).norm(), 1e-8 * H.norm());
  EXPECT_LT((g - J.transpose() * r).norm(), 1e-8 * g.norm());
}

TEST(DenseLeastSquares, NormalEquationsEqualCeresJacobianProducts) {
  ExpectNormalEquationsOfCeres(60);
  ExpectNormalEquationsOfCeres(3000);  // four chunks
}

// The chunks' sums are added in chunk order: one thread and all threads give bit-identical F, H and g.
TEST(DenseLeastSquares, LinearizationDoesNotDependOnTheNumberOfThreads) {
  const SE3 T_begin(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(1, 2, 0.1));
  const SE3 T_end(SO3::Exp(Eigen::Vector3d(0.02, 0.0, 0.38)), Eigen::Vector3d(2, 2.4, 0.1));
  const SweepScan scan = MakeScan(T_begin, T_end, 5000, 11);
  auto begin = PoseBlock(T_begin * SE3::Exp((Vector6d() << 0.3, -0.2, 0.1, 0.02, 0.01, -0.03).finished()));
  auto end = PoseBlock(T_end);
  DenseLeastSquares dense;
  dense.AddPoseBlock(begin.data());
  dense.AddPoseBlock(end.data());
  for (const auto& factor : scan.factors)
    dense.AddResidualBlock(factor.get(), scan.loss.get(), {begin.data(), end.data()});
  auto linearize = [&](std::size_t threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    double cost = 0;
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    EXPECT_TRUE(dense.Linearize(&cost, &H, &g));
    return std::make_tuple(cost, H, g);
  };
  const auto [cost_1, H_1, g_1] = linearize(1);
  const auto [cost_n, H_n, g_n] = linearize(tbb::info::default_concurrency());
  EXPECT_EQ(cost_1, cost_n);
  EXPECT_TRUE(H_1 == H_n);
  EXPECT_TRUE(g_1 == g_n);
}

TEST(DenseLeastSquares, RegistersADeskewedSweepLikeCeres) {
  const SE3 T_begin(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(1, 2, 0.1));
  const SE3 T_end(SO3::Exp(Eigen::Vector3d(0.02, 0.0, 0.42)), Eigen::Vector3d(2, 2.5, 0.12));
  const SweepScan scan = MakeScan(T_begin, T_end, 300, 11);
  const Vector6d offset_b = (Vector6d() << 0.2, -0.15, 0.05, 0.01, -0.01, 0.04).finished();
  const Vector6d offset_e = (Vector6d() << -0.1, 0.2, -0.05, -0.02, 0.01, -0.05).finished();
  auto dense_begin = PoseBlock(T_begin * SE3::Exp(offset_b)),
       dense_end = PoseBlock(T_end * SE3::Exp(offset_e));
  auto ceres_begin = dense_begin, ceres_end = dense_end;

  DenseLeastSquares dense;
  dense.AddPoseBlock(dense_begin.data());
  dense.AddPoseBlock(dense_end.data());
  PoseManifold manifold;
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(options);
  ceres_problem.AddParameterBlock(ceres_begin.data(), 7, &manifold);
  ceres_problem.AddParameterBlock(ceres_end.data(), 7, &manifold);
  for (const auto& factor : scan.factors) {
    dense.AddResidualBlock(factor.get(), scan.loss.get(), {dense_begin.data(), dense_end.data()});
    ceres_problem.AddResidualBlock(factor.get(), scan.loss.get(), ceres_begin.data(), ceres_end.data());
  }
  DenseSolverOptions dense_options;
  dense_options.max_iterations = 30;
  dense_options.max_time_s = 10;
  const DenseSolverSummary summary = dense.Solve(dense_options);
  ASSERT_TRUE(summary.usable);
  EXPECT_TRUE(summary.converged);
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = 30;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &ceres_problem, &ceres_summary);
  ASSERT_TRUE(ceres_summary.IsSolutionUsable());

  for (const auto& [dense_block, ceres_block, truth] :
       {std::tuple{&dense_begin, &ceres_begin, T_begin}, std::tuple{&dense_end, &ceres_end, T_end}}) {
    const SE3 dense_pose = PoseFromBlock(dense_block->data()),
              ceres_pose = PoseFromBlock(ceres_block->data());
    EXPECT_LT((dense_pose.inverse() * truth).translation().norm(), 1e-6);
    EXPECT_LT((dense_pose.inverse() * truth).so3().angle(), 1e-6);
    EXPECT_LT((dense_pose.inverse() * ceres_pose).translation().norm(), 1e-6);
  }
  EXPECT_NEAR(summary.final_cost, ceres_summary.final_cost, 1e-9);
}

// The tangent interface of the point-to-plane factors equals Ceres' ambient Jacobian times PlusJacobian.
TEST(DenseLeastSquares, TangentJacobiansEqualAmbientTimesPlusJacobian) {
  const Plane plane{Eigen::Vector3d(0.6, 0.0, 0.8), Eigen::Vector3d(1, 2, 3), 0.07};
  const SE3 T_body_lidar(SO3::Exp(Eigen::Vector3d(0.1, 0.2, -0.3)), Eigen::Vector3d(0.3, -0.1, 0.2));
  const auto begin = PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0.2, -0.1, 0.9)), Eigen::Vector3d(4, -2, 1)));
  const auto end = PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0.25, -0.05, 1.0)), Eigen::Vector3d(5, -1.8, 1.1)));
  const PointToPlaneFactor two(Eigen::Vector3d(3, -4, 0.5), 0.3, plane, T_body_lidar);
  const PointToPlaneFactorSinglePose one(Eigen::Vector3d(3, -4, 0.5), plane);
  const double* blocks[2] = {begin.data(), end.data()};
  double r_ambient = 0, r_tangent = 0, J_ambient[2][7], J_tangent[2][6], plus[2][42];
  double* ambient[2] = {J_ambient[0], J_ambient[1]};
  double* tangent[2] = {J_tangent[0], J_tangent[1]};
  PoseManifold().PlusJacobian(begin.data(), plus[0]);
  PoseManifold().PlusJacobian(end.data(), plus[1]);
  for (const ceres::CostFunction* cost :
       {static_cast<const ceres::CostFunction*>(&two), static_cast<const ceres::CostFunction*>(&one)}) {
    const int n = static_cast<int>(cost->parameter_block_sizes().size());
    ASSERT_TRUE(cost->Evaluate(blocks, &r_ambient, ambient));
    ASSERT_TRUE(dynamic_cast<const TangentJacobianCost*>(cost)->EvaluateTangent(blocks, &r_tangent, tangent));
    EXPECT_EQ(r_ambient, r_tangent);
    for (int k = 0; k < n; ++k) {
      const Eigen::Matrix<double, 1, 6> expected =
          Eigen::Map<Eigen::Matrix<double, 1, 7>>(J_ambient[k]) *
          Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(plus[k]);
      EXPECT_LT((expected - Eigen::Map<Eigen::Matrix<double, 1, 6>>(J_tangent[k])).norm(), 1e-12) << k;
    }
  }
}

}  // namespace
}  // namespace uf::estimator
