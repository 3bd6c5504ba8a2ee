// The LiDAR degeneracy score (schedule/lidar_degeneracy.h): hand-computed isotropies of plane layouts, and
// the score of LIO keyframes on simulated scenes whose geometry is known: a corridor and a tunnel leave their
// axis free, the urban street and the warehouse pin every direction.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/factors/projected_factor.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/estimator/schedule/lidar_degeneracy.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "odometry/types/so3.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/lio_test_support.h"

namespace uf::estimator {
namespace {

// H of unit-sigma point-to-plane residuals, each J = [n^T, (p x n)^T] (a rigid move of the points).
Matrix6d Information(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_normals) {
  Matrix6d H = Matrix6d::Zero();
  for (const auto& [p, n] : points_normals) {
    Vector6d J;
    J << n, p.cross(n);
    H += J * J.transpose();
  }
  return H;
}

TEST(LidarDegeneracy, HandComputedIsotropies) {
  // H_tt = diag(1, 1, 4): lambda_min 1 over the mean 2 -> 0.5; H_rr = diag(2, 2, 2) -> 1.
  Matrix6d H = Matrix6d::Zero();
  H.diagonal() << 1, 1, 4, 2, 2, 2;
  LidarDegeneracy d = AnalyzeLidarInformation(H, 100);
  EXPECT_NEAR(d.translation_isotropy, 0.5, 1e-12);
  EXPECT_NEAR(d.rotation_isotropy, 1.0, 1e-12);
  EXPECT_NEAR(d.score, 0.0, 1e-12);  // 0.5 >= kHealthyIsotropy
  EXPECT_NEAR(std::abs(d.weak_translation.dot(Eigen::Vector3d::UnitX())) +
                  std::abs(d.weak_translation.dot(Eigen::Vector3d::UnitY())),
              1.0, 1e-9);  // in the x-y plane (a tie)
  // H_tt = diag(0.02, 1, 1): 0.02 / (2.02 / 3) = 0.0297 -> D = 1 - 0.297 = 0.703, weak along x.
  H.diagonal() << 0.02, 1, 1, 2, 2, 2;
  d = AnalyzeLidarInformation(H, 100);
  EXPECT_NEAR(d.translation_isotropy, 0.02 / (2.02 / 3), 1e-12);
  EXPECT_NEAR(d.score, 1 - 0.02 / (2.02 / 3) / kHealthyIsotropy, 1e-12);
  EXPECT_NEAR(std::abs(d.weak_translation.x()), 1.0, 1e-12);
  // Too few matches, or nothing finite: degenerate.
  EXPECT_EQ(AnalyzeLidarInformation(H, 5).score, 1.0);
  H(0, 0) = NAN;
  EXPECT_EQ(AnalyzeLidarInformation(H, 100).score, 1.0);
}

TEST(LidarDegeneracy, ACorridorLeavesItsAxisFreeABoxPinsEverything) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> corridor, box;
  for (int i = -10; i <= 10; ++i) {
    const double x = i;
    for (const Eigen::Vector3d& n : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)}) {
      corridor.push_back({Eigen::Vector3d(x, 2 * n.y(), 1.5 * n.z() + 0.3), n});
      corridor.push_back({Eigen::Vector3d(x, -2 * n.y(), -1.5 * n.z() + 0.3), -n});
    }
    for (const Eigen::Vector3d& n :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)}) {
      // On each wall a cross of points through its centre.
      const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
      for (const Eigen::Vector3d& along : {Eigen::Vector3d(0.3 * x * e1), Eigen::Vector3d(0.3 * x * e2)}) {
        box.push_back({5 * n + along, n});
        box.push_back({-5 * n + along, -n});
      }
    }
  }
  const LidarDegeneracy in_corridor = AnalyzeLidarInformation(Information(corridor), 84);
  EXPECT_NEAR(in_corridor.translation_isotropy, 0.0, 1e-12);
  EXPECT_EQ(in_corridor.score, 1.0);
  EXPECT_NEAR(std::abs(in_corridor.weak_translation.x()), 1.0, 1e-9);
  const LidarDegeneracy in_box = AnalyzeLidarInformation(Information(box), 252);
  EXPECT_NEAR(in_box.translation_isotropy, 1.0, 1e-9);  // two walls along each axis
  EXPECT_NEAR(in_box.rotation_isotropy, 1.0, 1e-9);     // and the same crosses on each
  EXPECT_EQ(in_box.score, 0.0);
}

TEST(LidarDegeneracy, TheProjectorRemovesTheWeakDirectionsOnly) {
  Matrix6d H = Matrix6d::Zero();
  H.diagonal() << 0.02, 1, 1, 2, 2, 2;  // x translation weak
  Matrix6d expected = Matrix6d::Identity();
  expected(0, 0) = 0;
  EXPECT_LT((WeakDirectionProjector(H) - expected).norm(), 1e-12);
  H.diagonal() << 1, 1, 1, 0.01, 2, 0.05;  // rotations about x and z weak (0.01, 0.05 < 0.1 * 0.687)
  expected.setIdentity();
  expected(3, 3) = expected(5, 5) = 0;
  EXPECT_LT((WeakDirectionProjector(H) - expected).norm(), 1e-12);
  H.diagonal() << 1, 1, 4, 2, 2, 2;  // healthy
  EXPECT_TRUE(WeakDirectionProjector(H).isIdentity(0.0));
  EXPECT_TRUE(WeakDirectionProjector(Matrix6d::Zero()).isIdentity(0.0));
}

TEST(LidarDegeneracy, BesideAnotherSensorOnlyTheTranslationsItHoldsBetterAreDropped) {
  Matrix6d H = Matrix6d::Zero();
  H.diagonal() << 0.02, 1, 1, 2, 2, 2;  // x translation weak (0.02 < 0.1 * 0.673)
  Matrix6d without_x = Matrix6d::Identity();
  without_x(0, 0) = 0;
  // The other sensor holds x better than the scan (1 > 0.02): x goes; where it holds it less, x stays.
  EXPECT_LT((LooseTranslationProjector(H, Eigen::Vector3d(1, 0, 0).asDiagonal()) - without_x).norm(), 1e-12);
  EXPECT_TRUE(LooseTranslationProjector(H, Eigen::Vector3d(0.01, 5, 5).asDiagonal()).isIdentity(0.0));
  // Along a turned weak direction: W's information along it is what counts.
  const Eigen::Matrix3d R = SO3::Exp(Eigen::Vector3d(0, 0, 0.5)).matrix();
  Matrix6d H_turned = H;
  H_turned.block<3, 3>(0, 0) = R * H.block<3, 3>(0, 0) * R.transpose();
  const Eigen::Vector3d u = R.col(0);
  Matrix6d expected = Matrix6d::Identity();
  expected.block<3, 3>(0, 0) -= u * u.transpose();
  const Eigen::Matrix3d W =
      0.05 * u * u.transpose() + 0.001 * Eigen::Matrix3d::Identity();  // u^T W u = 0.051
  EXPECT_LT((LooseTranslationProjector(H_turned, W) - expected).norm(), 1e-9);
  // Rotations stay, however weak; a healthy scan keeps everything.
  H.diagonal() << 1, 1, 1, 0.01, 2, 0.05;
  EXPECT_TRUE(LooseTranslationProjector(H, 1e6 * Eigen::Matrix3d::Identity()).isIdentity(0.0));
  H.diagonal() << 1, 1, 4, 2, 2, 2;
  EXPECT_TRUE(LooseTranslationProjector(H, 1e6 * Eigen::Matrix3d::Identity()).isIdentity(0.0));
  EXPECT_TRUE(LooseTranslationProjector(Matrix6d::Zero(), Eigen::Matrix3d::Identity()).isIdentity(0.0));
}

TEST(LidarDegeneracy, AProjectedFactorKeepsTheResidualAndProjectsTheJacobians) {
  const Plane plane{Eigen::Vector3d(0.3, -0.5, 0.8).normalized(), Eigen::Vector3d(2, 1, -1), 0.05};
  const Eigen::Vector3d p_L(4, -2, 1);
  const SE3 T_body_lidar(SO3::Exp(Eigen::Vector3d(0.1, 0.2, -0.3)), Eigen::Vector3d(0.1, 0, 0.3));
  const PointToPlaneFactor reference(p_L, 0.3, plane, T_body_lidar);
  auto inner = std::make_unique<PointToPlaneFactor>(p_L, 0.3, plane, T_body_lidar);
  Matrix6d P = Matrix6d::Identity();
  P(0, 0) = 0;
  P.block<3, 3>(3, 3) -= Eigen::Vector3d(0, 0.6, 0.8) * Eigen::Vector3d(0, 0.6, 0.8).transpose();
  const ProjectedFactor projected(std::move(inner), P);
  const auto begin = PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0.2, -0.1, 0.4)), Eigen::Vector3d(1, 2, 3)));
  const auto end = PoseBlock(SE3(SO3::Exp(Eigen::Vector3d(0.25, -0.1, 0.5)), Eigen::Vector3d(1.5, 2, 3)));
  const double* blocks[2] = {begin.data(), end.data()};
  double r_ref = 0, r = 0;
  Eigen::Matrix<double, 1, 6> Jb_ref, Je_ref, Jb, Je;
  double* tangent_ref[2] = {Jb_ref.data(), Je_ref.data()};
  double* tangent[2] = {Jb.data(), Je.data()};
  ASSERT_TRUE(reference.EvaluateTangent(blocks, &r_ref, tangent_ref));
  ASSERT_TRUE(projected.EvaluateTangent(blocks, &r, tangent));
  EXPECT_EQ(r, r_ref);
  EXPECT_LT((Jb - Jb_ref * P).norm(), 1e-12);
  EXPECT_LT((Je - Je_ref * P).norm(), 1e-12);
  // The ambient Jacobians (for Ceres) lift the projected tangent ones.
  Eigen::Matrix<double, 1, 7> Ab, Ae;
  double* ambient[2] = {Ab.data(), Ae.data()};
  ASSERT_TRUE(projected.Evaluate(blocks, &r, ambient));
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
  PoseManifold().PlusJacobian(begin.data(), plus.data());
  EXPECT_LT((Ab * plus - Jb).norm(), 1e-9);
}

// LIO over `seconds` of a simulated scene (the default 32-beam LiDAR, no camera, wheel or GNSS): its
// keyframes' degeneracy.
std::vector<LidarDegeneracy> ScoreScene(const std::string& scene, double seconds) {
  uf::testing::TempDir dir;
  sim::SimulationConfig config;
  config.scene = scene;
  config.duration_s = seconds;
  config.camera.enabled = config.gnss.enabled = config.wheel.enabled = false;
  const std::filesystem::path folder = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, folder);
  EXPECT_TRUE(summary.ok()) << summary.error();
  auto odometry = LidarOdometry::Create(testing::SimulatedLioConfig());
  EXPECT_TRUE(odometry.ok());
  testing::FeedLio(folder, *odometry);
  std::vector<LidarDegeneracy> scores;
  for (const Keyframe& k : odometry->TakeFinished())
    if (k.lidar_degeneracy) scores.push_back(*k.lidar_degeneracy);
  return scores;
}

TEST(LidarDegeneracy, SimulatedScenesScoreAsTheirGeometry) {
  // Measured (10 s, seed 1, 32 beams): mean D corridor 0.97, tunnel 0.98, urban 0.16, warehouse 0.00.
  for (const char* scene : {"corridor", "tunnel"}) {
    const std::vector<LidarDegeneracy> scores = ScoreScene(scene, 4.0);
    ASSERT_GE(scores.size(), 30u) << scene;
    for (const LidarDegeneracy& d : scores) {
      EXPECT_GT(d.score, 0.8) << scene;
      EXPECT_GT(std::abs(d.weak_translation.x()), 0.95) << scene;  // both run along the world's x
    }
  }
  for (const char* scene : {"urban", "warehouse"}) {
    const std::vector<LidarDegeneracy> scores = ScoreScene(scene, 4.0);
    ASSERT_GE(scores.size(), 30u) << scene;
    double mean = 0;
    for (const LidarDegeneracy& d : scores) mean += d.score / static_cast<double>(scores.size());
    EXPECT_LT(mean, 0.4) << scene;
  }
}

}  // namespace
}  // namespace uf::estimator
