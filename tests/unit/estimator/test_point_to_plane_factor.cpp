// The point-to-plane factors against independent truth: hand-computed signed distances (a = 0, 1/2, 1; also
// with blocks changed in place between evaluations), the lever-arm variants against the fixed ones and
// numeric derivatives in t_BL,
// analytic Jacobians against central numeric derivatives taken in the pose tangent through
// PoseManifold::Plus (also for R_b = R_e), and a Ceres solve that registers a synthetic scan with motion
// during the sweep: with deskew it recovers both poses, without it (all points at a = 0) it cannot.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Matrix76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using RowVector6d = Eigen::Matrix<double, 1, 6>;
using RowVector7d = Eigen::Matrix<double, 1, 7>;

SO3 Rz(double angle) { return SO3::Exp(Eigen::Vector3d(0, 0, angle)); }

double Residual(const ceres::CostFunction& factor, const std::vector<const double*>& blocks) {
  double r = 0;
  factor.Evaluate(blocks.data(), &r, nullptr);
  return r;
}

TEST(PointToPlaneFactor, ResidualIsTheSignedDistanceAtThePointsTime) {
  // T_body_lidar = (Rz(90 deg), (0.5, 0, 0)): p_L = (1, 0, 0) -> p_B = (0.5, 1, 0).
  // Begin pose identity, end pose (Rz(90 deg), (2, 0, 0)). By hand:
  //   a = 0:   p_w = (0.5, 1, 0)
  //   a = 1:   p_w = Rz(90)(0.5, 1, 0) + (2, 0, 0) = (1, 0.5, 0)
  //   a = 1/2: p_w = Rz(45)(0.5, 1, 0) + (1, 0, 0) = (1 + (0.5 - 1) / sqrt2, (0.5 + 1) / sqrt2, 0)
  const SE3 T_body_lidar(Rz(kPi / 2), Eigen::Vector3d(0.5, 0, 0));
  const auto begin = PoseBlock(SE3());
  const auto end = PoseBlock(SE3(Rz(kPi / 2), Eigen::Vector3d(2, 0, 0)));
  const Plane x_plane{Eigen::Vector3d::UnitX(), Eigen::Vector3d(0.2, 7, -3), 0.1};  // r = (x - 0.2) / 0.1
  const Plane y_plane{-Eigen::Vector3d::UnitY(), Eigen::Vector3d(5, 0, 1), 0.5};    // r = -y / 0.5
  const double s = 1 / std::sqrt(2.0);
  const double expected_x[3] = {(0.5 - 0.2) / 0.1, (1 + (0.5 - 1) * s - 0.2) / 0.1, (1 - 0.2) / 0.1};
  const double expected_y[3] = {-1 / 0.5, -(1.5 * s) / 0.5, -0.5 / 0.5};
  const double alphas[3] = {0, 0.5, 1};
  for (int n = 0; n < 3; ++n) {
    const PointToPlaneFactor fx(Eigen::Vector3d(1, 0, 0), alphas[n], x_plane, T_body_lidar);
    const PointToPlaneFactor fy(Eigen::Vector3d(1, 0, 0), alphas[n], y_plane, T_body_lidar);
    EXPECT_NEAR(Residual(fx, {begin.data(), end.data()}), expected_x[n], 1e-12) << "a = " << alphas[n];
    EXPECT_NEAR(Residual(fy, {begin.data(), end.data()}), expected_y[n], 1e-12) << "a = " << alphas[n];
  }
  // The single-pose factor at the end pose equals the two-pose factor at a = 1.
  const PointToPlaneFactorSinglePose single(T_body_lidar * Eigen::Vector3d(1, 0, 0), x_plane);
  EXPECT_NEAR(Residual(single, {end.data()}), expected_x[2], 1e-12);
}

// The terms a scan's points share are kept per thread for the last (begin, end) values: blocks changed in
// place (as a solver does) must be seen. Same hand values as above: x_plane at a = 1/2 with the end pose
// (Rz(90 deg), (2, 0, 0)) gives (1 + (0.5 - 1) / sqrt2 - 0.2) / 0.1; with the end pose equal to the begin
// pose (identity), p_w = (0.5, 1, 0) for every a, so (0.5 - 0.2) / 0.1.
TEST(PointToPlaneFactor, SeesBlocksChangedInPlace) {
  const SE3 T_body_lidar(Rz(kPi / 2), Eigen::Vector3d(0.5, 0, 0));
  const Plane x_plane{Eigen::Vector3d::UnitX(), Eigen::Vector3d(0.2, 7, -3), 0.1};
  const PointToPlaneFactor factor(Eigen::Vector3d(1, 0, 0), 0.5, x_plane, T_body_lidar);
  const double moving = (1 + (0.5 - 1) / std::sqrt(2.0) - 0.2) / 0.1, still = (0.5 - 0.2) / 0.1;
  const auto begin = PoseBlock(SE3());
  auto end = PoseBlock(SE3(Rz(kPi / 2), Eigen::Vector3d(2, 0, 0)));
  for (int round = 0; round < 2; ++round) {
    end = PoseBlock(SE3(Rz(kPi / 2), Eigen::Vector3d(2, 0, 0)));
    EXPECT_NEAR(Residual(factor, {begin.data(), end.data()}), moving, 1e-12) << round;
    end = PoseBlock(SE3());
    EXPECT_NEAR(Residual(factor, {begin.data(), end.data()}), still, 1e-12) << round;
  }
}

// Tangent Jacobian of a residual w.r.t. block k by central differences through PoseManifold::Plus.
RowVector6d NumericTangentJacobian(const ceres::CostFunction& factor,
                                   std::vector<std::array<double, 7>> poses, int k) {
  const PoseManifold manifold;
  const double h = 1e-6;
  RowVector6d J;
  for (int i = 0; i < 6; ++i) {
    double delta[6] = {0, 0, 0, 0, 0, 0};
    double r[2];
    for (int sign = 0; sign < 2; ++sign) {
      delta[i] = sign == 0 ? h : -h;
      std::vector<std::array<double, 7>> moved = poses;
      manifold.Plus(poses[k].data(), delta, moved[k].data());
      std::vector<const double*> blocks;
      for (const auto& pose : moved) blocks.push_back(pose.data());
      r[sign] = Residual(factor, blocks);
    }
    J(i) = (r[0] - r[1]) / (2 * h);
  }
  return J;
}

// The analytic ambient Jacobian times PlusJacobian is the tangent Jacobian.
RowVector6d AnalyticTangentJacobian(const ceres::CostFunction& factor,
                                    const std::vector<std::array<double, 7>>& poses, int k) {
  std::vector<const double*> blocks;
  for (const auto& pose : poses) blocks.push_back(pose.data());
  std::vector<RowVector7d> ambient(poses.size());
  std::vector<double*> jacobians;
  for (auto& J : ambient) jacobians.push_back(J.data());
  double r = 0;
  factor.Evaluate(blocks.data(), &r, jacobians.data());
  Matrix76 plus;
  PoseManifold().PlusJacobian(poses[k].data(), plus.data());
  return ambient[k] * plus;
}

double RelativeError(const RowVector6d& analytic, const RowVector6d& numeric) {
  return (analytic - numeric).norm() / std::max(numeric.norm(), 1e-12);
}

TEST(PointToPlaneFactor, JacobiansMatchNumericDerivativesInTheTangent) {
  std::mt19937_64 random(17);
  std::normal_distribution<double> normal;
  auto vector = [&](double scale) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * scale;
  };
  const double alphas[] = {0, 0.13, 0.5, 0.77, 1};
  for (int trial = 0; trial < 20; ++trial) {
    const SE3 T_body_lidar(SO3::Exp(vector(0.5)), vector(1));
    const SE3 T_b(SO3::Exp(vector(1.0)), vector(10));
    // Every fourth trial the rotations are equal (a scan without rotation): Log(R_b^T R_e) = 0.
    const SO3 R_e = trial % 4 == 0 ? T_b.so3() : T_b.so3() * SO3::Exp(vector(0.3));
    const SE3 T_e(R_e, T_b.translation() + vector(1));
    const Plane plane{vector(1).normalized(), vector(10), 0.05 + std::abs(normal(random))};
    const std::vector<std::array<double, 7>> poses = {PoseBlock(T_b), PoseBlock(T_e)};
    for (double alpha : alphas) {
      const PointToPlaneFactor factor(vector(20), alpha, plane, T_body_lidar);
      for (int k = 0; k < 2; ++k) {
        const RowVector6d numeric = NumericTangentJacobian(factor, poses, k);
        const RowVector6d analytic = AnalyticTangentJacobian(factor, poses, k);
        if ((k == 0 && alpha == 1) || (k == 1 && alpha == 0)) {  // the block has no say at this time
          EXPECT_LT(analytic.norm(), 1e-12);
          EXPECT_LT(numeric.norm(), 1e-7);
          continue;
        }
        EXPECT_LT(RelativeError(analytic, numeric), 1e-6)
            << "trial " << trial << " a " << alpha << " block " << k << "\nanalytic " << analytic
            << "\nnumeric  " << numeric;
      }
    }
    const PointToPlaneFactorSinglePose single(vector(20), plane);
    EXPECT_LT(RelativeError(AnalyticTangentJacobian(single, {poses[0]}, 0),
                            NumericTangentJacobian(single, {poses[0]}, 0)),
              1e-6);
  }
}

// The lever-arm variants take t_BL from a block: at the same T_body_lidar they give the fixed factors'
// residuals and pose Jacobians, and their Jacobian in t_BL matches central differences (a residual linear in
// t_BL, so the match is to rounding).
TEST(PointToPlaneFactor, LeverVariantsMatchTheFixedFactorsAndNumericDerivatives) {
  std::mt19937_64 random(29);
  std::normal_distribution<double> normal;
  auto vector = [&](double scale) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * scale;
  };
  for (int trial = 0; trial < 10; ++trial) {
    const SE3 T_body_lidar(SO3::Exp(vector(0.5)), vector(0.3));
    const SE3 T_b(SO3::Exp(vector(1.0)), vector(10));
    const SE3 T_e(T_b.so3() * SO3::Exp(vector(0.3)), T_b.translation() + vector(1));
    const Plane plane{vector(1).normalized(), vector(10), 0.05 + std::abs(normal(random))};
    const Eigen::Vector3d p_L = vector(20);
    const double alpha = trial / 9.0;
    const Eigen::Matrix3d R_BL = T_body_lidar.so3().matrix();
    std::array<double, 3> t_BL;
    Eigen::Map<Eigen::Vector3d>(t_BL.data()) = T_body_lidar.translation();
    const auto b = PoseBlock(T_b), e = PoseBlock(T_e);

    const PointToPlaneFactor fixed(p_L, alpha, plane, T_body_lidar);
    const PointToPlaneLeverFactor lever(p_L, alpha, plane, R_BL);
    const PointToPlaneFactorSinglePose fixed_single(T_body_lidar * p_L, plane);
    const PointToPlaneLeverFactorSinglePose lever_single(p_L, plane, R_BL);
    double r_fixed = 0, r_lever = 0, r_fixed_single = 0, r_lever_single = 0;
    RowVector6d J_fixed[2], J_lever[2], J_fixed_single, J_lever_single;
    Eigen::RowVector3d J_t, J_t_single;
    {
      const double* blocks[2] = {b.data(), e.data()};
      double* jacobians[2] = {J_fixed[0].data(), J_fixed[1].data()};
      fixed.EvaluateTangent(blocks, &r_fixed, jacobians);
      const double* lever_blocks[3] = {b.data(), e.data(), t_BL.data()};
      double* lever_jacobians[3] = {J_lever[0].data(), J_lever[1].data(), J_t.data()};
      lever.EvaluateTangent(lever_blocks, &r_lever, lever_jacobians);
      const double* single_blocks[1] = {e.data()};
      double* single_jacobians[1] = {J_fixed_single.data()};
      fixed_single.EvaluateTangent(single_blocks, &r_fixed_single, single_jacobians);
      const double* lever_single_blocks[2] = {e.data(), t_BL.data()};
      double* lever_single_jacobians[2] = {J_lever_single.data(), J_t_single.data()};
      lever_single.EvaluateTangent(lever_single_blocks, &r_lever_single, lever_single_jacobians);
    }
    EXPECT_NEAR(r_lever, r_fixed, 1e-9 * std::max(1.0, std::abs(r_fixed)));
    EXPECT_NEAR(r_lever_single, r_fixed_single, 1e-9 * std::max(1.0, std::abs(r_fixed_single)));
    for (int k = 0; k < 2; ++k) EXPECT_LT((J_lever[k] - J_fixed[k]).norm(), 1e-9 * (1 + J_fixed[k].norm()));
    EXPECT_LT((J_lever_single - J_fixed_single).norm(), 1e-9 * (1 + J_fixed_single.norm()));
    // d r / d t_BL by central differences.
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> plus = t_BL, minus = t_BL;
      plus[i] += h;
      minus[i] -= h;
      const double numeric = (Residual(lever, {b.data(), e.data(), plus.data()}) -
                              Residual(lever, {b.data(), e.data(), minus.data()})) /
                             (2 * h);
      const double numeric_single = (Residual(lever_single, {e.data(), plus.data()}) -
                                     Residual(lever_single, {e.data(), minus.data()})) /
                                    (2 * h);
      EXPECT_NEAR(J_t(i), numeric, 1e-6 * (1 + std::abs(numeric))) << "trial " << trial << " axis " << i;
      EXPECT_NEAR(J_t_single(i), numeric_single, 1e-6 * (1 + std::abs(numeric_single)))
          << "trial " << trial << " axis " << i;
    }
    // The ambient Jacobians (Ceres' interface) agree in the Euclidean block with the tangent ones.
    Eigen::Matrix<double, 1, 7, Eigen::RowMajor> A_b, A_e;
    Eigen::RowVector3d A_t;
    const double* blocks[3] = {b.data(), e.data(), t_BL.data()};
    double* jacobians[3] = {A_b.data(), A_e.data(), A_t.data()};
    double r = 0;
    lever.Evaluate(blocks, &r, jacobians);
    EXPECT_LT((A_t - J_t).norm(), 1e-12);
    Matrix76 plus_b;
    PoseManifold().PlusJacobian(b.data(), plus_b.data());
    EXPECT_LT((A_b * plus_b - J_lever[0]).norm(), 1e-9 * (1 + J_lever[0].norm()));
  }
}

// A synthetic sweep: points on eight planes of different orientations, each measured at its own time a_i
// while the body moves from T_b to T_e (0.8 m and 6 deg during the sweep).
struct SyntheticSweep {
  SE3 T_body_lidar{SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(0.2, -0.1, 0.8)};
  SE3 T_b{SO3::Exp(Eigen::Vector3d(0.02, 0.01, 0.4)), Eigen::Vector3d(3, -2, 0.5)};
  SE3 T_e{T_b * SE3(SO3::Exp(Eigen::Vector3d(0.01, -0.01, 6 * kPi / 180)), Eigen::Vector3d(0.8, 0.1, 0.02))};
  std::vector<Plane> planes;
  std::vector<Eigen::Vector3d> points_lidar;
  std::vector<double> alphas;
  std::vector<int> plane_of_point;

  SyntheticSweep() {
    const Eigen::Vector3d normals[8] = {{0, 0, 1},      {1, 0, 0},  {0, 1, 0},   {-1, 0.2, 0},
                                        {0.1, -1, 0.1}, {0, 0, -1}, {1, 1, 0.3}, {-0.5, 1, 0.8}};
    const double distances[8] = {2, 15, 12, 18, 10, 6, 20, 14};  // plane offsets from T_b's origin, m
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d n = normals[k].normalized();
      planes.push_back(Plane{n, T_b.translation() + distances[k] * n, 0.05});
    }
    std::mt19937_64 random(23);
    std::uniform_real_distribution<double> extent(-8, 8);
    const int count = 800;
    for (int i = 0; i < count; ++i) {
      const int k = i % 8;
      const double alpha = static_cast<double>(i) / (count - 1);
      // A point on plane k: its point plus two in-plane offsets.
      const Eigen::Vector3d n = planes[k].normal;
      const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
      const Eigen::Vector3d p_w = planes[k].point + extent(random) * e1 + extent(random) * e2;
      const SE3 T_world_body = Interpolate(T_b, T_e, alpha);
      points_lidar.push_back((T_world_body * T_body_lidar).inverse() * p_w);
      alphas.push_back(alpha);
      plane_of_point.push_back(k);
    }
  }
};

// Pose errors (translation m, rotation deg) of a solved block against the truth.
std::pair<double, double> PoseError(const std::array<double, 7>& block, const SE3& truth) {
  const SE3 solved = PoseFromBlock(block.data());
  return {(solved.translation() - truth.translation()).norm(),
          (truth.so3().inverse() * solved.so3()).angle() * 180 / kPi};
}

std::array<double, 7> Perturbed(const SE3& T, const Eigen::Vector3d& dt, const Eigen::Vector3d& dphi) {
  return PoseBlock(SE3(T.so3() * SO3::Exp(dphi), T.translation() + dt));
}

TEST(PointToPlaneFactor, CeresRegistersADeskewedSweep) {
  const SyntheticSweep sweep;
  auto begin = Perturbed(sweep.T_b, {0.3, -0.2, 0.1}, {0.02, -0.03, 0.05});
  auto end = Perturbed(sweep.T_e, {-0.2, 0.3, -0.1}, {-0.03, 0.02, -0.04});
  ceres::Problem problem;
  for (std::size_t i = 0; i < sweep.points_lidar.size(); ++i)
    problem.AddResidualBlock(
        new PointToPlaneFactor(sweep.points_lidar[i], sweep.alphas[i], sweep.planes[sweep.plane_of_point[i]],
                               sweep.T_body_lidar),
        new ceres::HuberLoss(1.0), begin.data(), end.data());
  problem.SetManifold(begin.data(), new PoseManifold);
  problem.SetManifold(end.data(), new PoseManifold);
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const auto [begin_m, begin_deg] = PoseError(begin, sweep.T_b);
  const auto [end_m, end_deg] = PoseError(end, sweep.T_e);
  EXPECT_LT(begin_m, 1e-3);
  EXPECT_LT(begin_deg, 0.01);
  EXPECT_LT(end_m, 1e-3);
  EXPECT_LT(end_deg, 0.01);
}

TEST(PointToPlaneFactor, WithoutDeskewTheSameSweepRegistersVisiblyWorse) {
  // All points treated as measured at the scan begin (a = 0): one pose, the sweep's motion is ignored.
  const SyntheticSweep sweep;
  auto begin = Perturbed(sweep.T_b, {0.3, -0.2, 0.1}, {0.02, -0.03, 0.05});
  ceres::Problem problem;
  for (std::size_t i = 0; i < sweep.points_lidar.size(); ++i)
    problem.AddResidualBlock(new PointToPlaneFactorSinglePose(sweep.T_body_lidar * sweep.points_lidar[i],
                                                              sweep.planes[sweep.plane_of_point[i]]),
                             new ceres::HuberLoss(1.0), begin.data());
  problem.SetManifold(begin.data(), new PoseManifold);
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const auto [m, deg] = PoseError(begin, sweep.T_b);
  // 0.8 m and 6 deg of motion during the sweep: the skewed scan lands centimetres to decimetres off.
  EXPECT_GT(m, 0.05) << "rotation error " << deg << " deg";
  EXPECT_GT(summary.final_cost, 100 * 1e-6);
}

}  // namespace
}  // namespace uf::estimator
