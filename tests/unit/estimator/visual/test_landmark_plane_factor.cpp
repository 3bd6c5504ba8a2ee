// The landmark's map-plane factor (LVIO) against independent truth: hand-computed signed distances (with and
// without a time offset), zero on the plane, and the analytic Jacobians (anchor pose, extrinsic, inverse
// depth, time offset) against central numeric derivatives through PoseManifold::Plus, for random states;
// Ceres' ambient Jacobians times PlusJacobian against the tangent ones.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "odometry/estimator/factors/landmark_plane_factor.h"
#include "tests/unit/estimator/visual/factor_blocks.h"

namespace uf::estimator {
namespace {

using RowVector6d = Eigen::Matrix<double, 1, 6>;
using RowVector7d = Eigen::Matrix<double, 1, 7>;
using Matrix76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;

using test::FactorBlocks;

// The factor's four blocks: pose_i, T_imu_cam, lambda, t_d.
FactorBlocks MakeBlocks(const SE3& pose_i, const SE3& T_imu_cam, double lambda, double td) {
  return FactorBlocks::Of({pose_i, T_imu_cam}, {lambda, td});
}

double Residual(const LandmarkPlaneFactor& f, const FactorBlocks& b) { return test::Residuals(f, b)[0]; }

TEST(LandmarkPlaneFactor, ResidualIsTheSignedDistanceToThePlaneInSigmas) {
  // The anchor camera at the origin sees u = (0.2, -0.1) at inverse depth 0.5: P = (0.4, -0.2, 2). The plane
  // z = 1.5 (normal +z) with sigma 0.1: r = (2 - 1.5) / 0.1 = 5.
  const Plane plane{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(3, -1, 1.5), 0.1};
  const LandmarkPlaneFactor f({{0.2, -0.1}, {0, 0}}, 0, plane);
  EXPECT_NEAR(Residual(f, MakeBlocks(SE3(), SE3(), 0.5, 0)), 5, 1e-12);
  // The body 0.5 m back along z (P_w = (0.4, -0.2, 1.5)): on the plane.
  EXPECT_NEAR(Residual(f, MakeBlocks(SE3(SO3(), Eigen::Vector3d(0, 0, -0.5)), SE3(), 0.5, 0)), 0, 1e-12);
  // The plane x = 0.3 (normal +x) against the feature moving at (1, 0)/s: t_d = 0.01 s (t_d0 = 0) moves the
  // ray back to u' = (0.19, -0.1), P = (0.38, -0.2, 2): r = (0.38 - 0.3) / 0.1 = 0.8.
  const Plane wall{Eigen::Vector3d::UnitX(), Eigen::Vector3d(0.3, 0, 0), 0.1};
  const LandmarkPlaneFactor moving({{0.2, -0.1}, {1, 0}}, 0, wall);
  EXPECT_NEAR(Residual(moving, MakeBlocks(SE3(), SE3(), 0.5, 0.01)), 0.8, 1e-12);
}

TEST(LandmarkPlaneFactor, JacobiansMatchNumericDerivatives) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * s;
  };
  for (int trial = 0; trial < 40; ++trial) {
    const SE3 T_imu_cam(SO3::Exp(vec(0.3)), vec(0.2));
    const SE3 pose_i(SO3::Exp(vec(0.5)), vec(3));
    const Eigen::Vector3d P_c(normal(rng), normal(rng), 2 + 6 * std::abs(normal(rng)) / 3);
    const Plane plane{vec(1).normalized(), (pose_i * T_imu_cam) * P_c + vec(0.05),
                      0.02 + std::abs(normal(rng)) * 0.05};
    const FeatureObservation anchor{P_c.head<2>() / P_c.z(), Eigen::Vector2d(normal(rng), normal(rng)) * 0.3};
    const LandmarkPlaneFactor f(anchor, 0.003, plane);
    const FactorBlocks b = MakeBlocks(pose_i, T_imu_cam, 1.1 / P_c.z(), -0.004);

    std::vector<std::vector<double>> tangent = {std::vector<double>(6), std::vector<double>(6),
                                                std::vector<double>(1), std::vector<double>(1)};
    std::vector<double*> tangent_ptr;
    for (auto& t : tangent) tangent_ptr.push_back(t.data());
    double r = 0;
    ASSERT_TRUE(f.EvaluateTangent(b.Pointers().data(), &r, tangent_ptr.data()));
    for (int k = 0; k < 4; ++k) {
      const Eigen::MatrixXd numeric = test::NumericTangentJacobian(f, b, k);
      for (int i = 0; i < b.TangentSize(k); ++i)
        EXPECT_NEAR(tangent[k][i], numeric(0, i), 1e-5 * std::max(1.0, std::abs(numeric(0, i))))
            << "trial " << trial << " block " << k << " column " << i;
    }
    // Ceres' ambient Jacobians times PlusJacobian give the tangent ones.
    std::vector<std::vector<double>> ambient = {std::vector<double>(7), std::vector<double>(7),
                                                std::vector<double>(1), std::vector<double>(1)};
    std::vector<double*> ambient_ptr;
    for (auto& a : ambient) ambient_ptr.push_back(a.data());
    ASSERT_TRUE(f.Evaluate(b.Pointers().data(), &r, ambient_ptr.data()));
    for (int k = 0; k < 2; ++k) {
      Matrix76 plus;
      PoseManifold().PlusJacobian(b.values[k].data(), plus.data());
      const RowVector6d through = Eigen::Map<const RowVector7d>(ambient[k].data()) * plus;
      EXPECT_LT((through - Eigen::Map<const RowVector6d>(tangent[k].data())).norm(), 1e-9) << "block " << k;
    }
    EXPECT_EQ(ambient[2][0], tangent[2][0]);
    EXPECT_EQ(ambient[3][0], tangent[3][0]);
  }
}

}  // namespace
}  // namespace uf::estimator
