// The visual reprojection factor against independent truth: a hand-computed residual, zero residual at
// simulated truth, and the analytic Jacobians (poses, extrinsic, inverse depth, time offset) against central
// numeric derivatives through PoseManifold::Plus, for random states; the same with the target seen by a
// stereo rig's second camera.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "odometry/estimator/factors/reprojection_factor.h"
#include "tests/unit/estimator/visual/factor_blocks.h"

namespace uf::estimator {
namespace {

using Matrix26 = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;
using Matrix27 = Eigen::Matrix<double, 2, 7, Eigen::RowMajor>;
using Matrix76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;

using test::FactorBlocks;

// The factor's five blocks: pose_i, pose_j, T_imu_cam, lambda, t_d.
FactorBlocks MakeBlocks(const SE3& pose_i, const SE3& pose_j, const SE3& T_imu_cam, double lambda,
                        double td) {
  return FactorBlocks::Of({pose_i, pose_j, T_imu_cam}, {lambda, td});
}

Eigen::Vector2d Residual(const ReprojectionFactor& f, const FactorBlocks& b) { return test::Residuals(f, b); }

TEST(ReprojectionFactor, ResidualIsTheScaledNormalizedError) {
  // Anchor camera at the origin sees u_i = (0.1, -0.2) at depth 2: P = (0.2, -0.4, 2). Camera j is 0.5 m
  // along x: P_cj = (-0.3, -0.4, 2), pi = (-0.15, -0.2). Observed (-0.14, -0.2), s = 100: r = (-1, 0).
  const ReprojectionFactor f({{0.1, -0.2}, {0, 0}}, {{-0.14, -0.2}, {0, 0}}, 0, 0, 100);
  const FactorBlocks b = MakeBlocks(SE3(), SE3(SO3(), Eigen::Vector3d(0.5, 0, 0)), SE3(), 0.5, 0);
  EXPECT_LT((Residual(f, b) - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
  // A time offset moves both observations back along their velocities: t_d = 0.01 s with the target
  // moving at (1, 0)/s gives u_j' = (-0.15, -0.2): r = 0.
  const ReprojectionFactor moving({{0.1, -0.2}, {0, 0}}, {{-0.14, -0.2}, {1, 0}}, 0, 0, 100);
  const FactorBlocks shifted = MakeBlocks(SE3(), SE3(SO3(), Eigen::Vector3d(0.5, 0, 0)), SE3(), 0.5, 0.01);
  EXPECT_LT(Residual(moving, shifted).norm(), 1e-12);
}

TEST(ReprojectionFactor, ASecondCameraSeesThroughTheRigExtrinsic) {
  // As above, but the target is the rig's right camera 0.5 m to the right of the anchor camera at the same
  // pose (p_right = p_left - (0.5, 0, 0)): P_t = (-0.3, -0.4, 2), pi = (-0.15, -0.2), r = (-1, 0).
  const SE3 T_right_left(SO3(), Eigen::Vector3d(-0.5, 0, 0));
  const ReprojectionFactor f({{0.1, -0.2}, {0, 0}}, {{-0.14, -0.2}, {0, 0}}, 0, 0, 100, T_right_left);
  EXPECT_LT((Residual(f, MakeBlocks(SE3(), SE3(), SE3(), 0.5, 0)) - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
}

TEST(ReprojectionFactor, JacobiansMatchNumericDerivatives) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * s;
  };
  for (int trial = 0; trial < 40; ++trial) {
    // Half the trials see the target through a second camera ~0.3 m to the right (stereo).
    const SE3 T_target_cam =
        trial % 2 == 0 ? SE3() : SE3(SO3::Exp(vec(0.05)), Eigen::Vector3d(-0.3, 0, 0) + vec(0.02));
    const SE3 T_imu_cam(SO3::Exp(vec(0.3)), vec(0.2));
    const SE3 pose_i(SO3::Exp(vec(0.5)), vec(3));
    const SE3 pose_j = pose_i * SE3(SO3::Exp(vec(0.1)), vec(0.5));
    // A landmark 4-10 m in front of the anchor camera, observed by both.
    const SE3 cam_i = pose_i * T_imu_cam, cam_j = pose_j * T_imu_cam;
    const Eigen::Vector3d P_ci(normal(rng), normal(rng), 4 + 6 * std::abs(normal(rng)) / 3);
    const Eigen::Vector3d P_cj = T_target_cam * (cam_j.inverse() * (cam_i * P_ci));
    ASSERT_GT(P_cj.z(), 0.5);
    const FeatureObservation anchor{P_ci.head<2>() / P_ci.z() + Eigen::Vector2d(0.01, -0.02),
                                    Eigen::Vector2d(normal(rng), normal(rng)) * 0.3};
    const FeatureObservation target{P_cj.head<2>() / P_cj.z(),
                                    Eigen::Vector2d(normal(rng), normal(rng)) * 0.3};
    const ReprojectionFactor f(anchor, target, 0.002, -0.004, 300, T_target_cam);
    const FactorBlocks b = MakeBlocks(pose_i, pose_j, T_imu_cam, 1 / P_ci.z() * 1.1, 0.01);

    std::vector<std::vector<double>> tangent = {std::vector<double>(12), std::vector<double>(12),
                                                std::vector<double>(12), std::vector<double>(2),
                                                std::vector<double>(2)};
    std::vector<double*> tangent_ptr;
    for (auto& t : tangent) tangent_ptr.push_back(t.data());
    Eigen::Vector2d r;
    f.EvaluateTangent(b.Pointers().data(), r.data(), tangent_ptr.data());
    for (int k = 0; k < 5; ++k) {
      const Eigen::MatrixXd numeric = test::NumericTangentJacobian(f, b, k);
      const Eigen::MatrixXd analytic =
          Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
              tangent[k].data(), 2, b.TangentSize(k));
      EXPECT_LT((analytic - numeric).norm(), 1e-5 * std::max(1.0, numeric.norm()))
          << "trial " << trial << " block " << k;
    }
    // Ceres' ambient Jacobians times PlusJacobian give the tangent ones.
    std::vector<std::vector<double>> ambient = {std::vector<double>(14), std::vector<double>(14),
                                                std::vector<double>(14), std::vector<double>(2),
                                                std::vector<double>(2)};
    std::vector<double*> ambient_ptr;
    for (auto& a : ambient) ambient_ptr.push_back(a.data());
    f.Evaluate(b.Pointers().data(), r.data(), ambient_ptr.data());
    for (int k = 0; k < 3; ++k) {
      Matrix76 plus;
      PoseManifold().PlusJacobian(b.values[k].data(), plus.data());
      const Matrix26 through = Eigen::Map<const Matrix27>(ambient[k].data()) * plus;
      EXPECT_LT((through - Eigen::Map<const Matrix26>(tangent[k].data())).norm(), 1e-9) << "block " << k;
    }
  }
}

}  // namespace
}  // namespace uf::estimator
