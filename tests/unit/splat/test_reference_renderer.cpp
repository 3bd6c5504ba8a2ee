// The CPU reference renderer against hand-computed values: projection of one Gaussian (mean, conic, radius,
// tiles), pixel values at the centre and at known offsets, front-to-back blending of two Gaussians, the
// transmittance cut-off, SH direction dependence and orthonormality, culling, and EWA against a numeric
// Jacobian of the pinhole projection.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/cpu_reference/spherical_harmonics.h"

namespace uf::splat {
namespace {

// 96 x 64 px, fx = fy = 100, principal point (48, 32), camera frame = world frame unless a pose is given.
SplatCamera TestCamera(const SE3& T_world_camera = SE3()) {
  SplatCamera camera;
  camera.pinhole = {.width = 96, .height = 64, .fx = 100, .fy = 100, .cx = 48, .cy = 32};
  camera.T_world_camera = T_world_camera;
  return camera;
}

float Logit(float p) { return std::log(p / (1 - p)); }

// One isotropic Gaussian, sigma = 0.1 m, at depth 5 on the optical axis, opacity 0.5.
GaussianModel OneGaussian() {
  GaussianModel model;
  model.AddConstantColor({0, 0, 5}, Eigen::Vector3f::Constant(std::log(0.1f)), Eigen::Quaternionf::Identity(),
                         0.0f, {0.2f, 0.4f, 0.6f});
  return model;
}

TEST(ReferenceRenderer, ProjectsAnIsotropicGaussianStraightAhead) {
  const ProjectedGaussian g =
      ProjectGaussian(OneGaussian(), 0, MakeFloatCamera(TestCamera()), RenderSettings());
  ASSERT_FALSE(g.culled);
  EXPECT_FLOAT_EQ(g.mean_2d.x(), 48.0f);
  EXPECT_FLOAT_EQ(g.mean_2d.y(), 32.0f);
  // J = diag(fx / z) = 20 px/m: Sigma_2D = 400 * 0.01 + 0.3 = 4.3 px^2, conic = 1 / 4.3, radius ceil(3
  // sqrt(4.3)) = 7.
  EXPECT_NEAR(g.conic.x(), 1.0f / 4.3f, 1e-6f);
  EXPECT_NEAR(g.conic.y(), 0.0f, 1e-7f);
  EXPECT_NEAR(g.conic.z(), 1.0f / 4.3f, 1e-6f);
  EXPECT_EQ(g.radius, 7);
  EXPECT_FLOAT_EQ(g.depth, 5.0f);
  EXPECT_FLOAT_EQ(g.opacity, 0.5f);
  EXPECT_NEAR(g.color.x(), 0.2f, 1e-6f);
  EXPECT_NEAR(g.color.z(), 0.6f, 1e-6f);
  // Tiles x: [int(41 / 16), int(70 / 16)) = [2, 4); y: [int(25 / 16), int(54 / 16)) = [1, 3).
  EXPECT_EQ(g.tile_min, Eigen::Vector2i(2, 1));
  EXPECT_EQ(g.tile_max, Eigen::Vector2i(4, 3));
}

TEST(ReferenceRenderer, PixelValuesOfOneGaussian) {
  const SplatCamera camera = TestCamera();
  RenderSettings settings;
  settings.background = {0.1f, 0.2f, 0.3f};
  const RenderedView view = RenderReference(OneGaussian(), camera, settings);
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * camera.pinhole.width + x; };
  // Centre: alpha = 0.5, rgb = 0.5 colour + 0.5 background; median depth reached (T = 0.5).
  const std::size_t centre = at(48, 32);
  EXPECT_NEAR(view.alpha[centre], 0.5f, 1e-6f);
  EXPECT_NEAR(view.rgb[3 * centre + 0], 0.5f * 0.2f + 0.5f * 0.1f, 1e-6f);
  EXPECT_NEAR(view.rgb[3 * centre + 2], 0.5f * 0.6f + 0.5f * 0.3f, 1e-6f);
  EXPECT_FLOAT_EQ(view.depth[centre], 5.0f);
  EXPECT_FLOAT_EQ(view.expected_depth[centre], 5.0f);
  // Offset d = (2, 1): alpha = 0.5 exp(-0.5 * 5 / 4.3); T > 0.5, so no median depth.
  const std::size_t offset = at(50, 33);
  const float alpha = 0.5f * std::exp(-0.5f * 5.0f / 4.3f);
  EXPECT_NEAR(view.alpha[offset], alpha, 1e-6f);
  EXPECT_NEAR(view.rgb[3 * offset + 1], alpha * 0.4f + (1 - alpha) * 0.2f, 1e-6f);
  EXPECT_EQ(view.depth[offset], RenderedView::kNoDepth);
  EXPECT_FLOAT_EQ(view.expected_depth[offset], 5.0f);
  // d = (6, 3): alpha = 0.5 exp(-45 / 8.6) = 0.0027 < 1/255 is skipped; d = (6, 0): 0.0076 is not.
  EXPECT_EQ(view.alpha[at(54, 35)], 0.0f);
  EXPECT_NEAR(view.alpha[at(54, 32)], 0.5f * std::exp(-18.0f / 4.3f), 1e-7f);
  // Outside the Gaussian's tiles: background only.
  EXPECT_EQ(view.alpha[at(10, 10)], 0.0f);
  EXPECT_FLOAT_EQ(view.rgb[3 * at(10, 10) + 2], 0.3f);
  EXPECT_EQ(view.expected_depth[at(10, 10)], RenderedView::kNoDepth);
}

TEST(ReferenceRenderer, BlendsTwoGaussiansFrontToBack) {
  // Far (blue, opacity 0.8, z = 6) added first, near (red, opacity 0.6, z = 4) second: order is by depth.
  GaussianModel model;
  const Eigen::Vector3f log_scale = Eigen::Vector3f::Constant(std::log(0.1f));
  model.AddConstantColor({0, 0, 6}, log_scale, Eigen::Quaternionf::Identity(), Logit(0.8f), {0, 0, 1});
  model.AddConstantColor({0, 0, 4}, log_scale, Eigen::Quaternionf::Identity(), Logit(0.6f), {1, 0, 0});
  const RenderedView view = RenderReference(model, TestCamera(), RenderSettings());
  const std::size_t centre = 32 * 96 + 48;
  // C = 0.6 red + (1 - 0.6) 0.8 blue; T = 0.4 * 0.2; median depth: T = 0.4 <= 0.5 after the near one.
  EXPECT_NEAR(view.rgb[3 * centre + 0], 0.6f, 1e-5f);
  EXPECT_NEAR(view.rgb[3 * centre + 1], 0.0f, 1e-5f);
  EXPECT_NEAR(view.rgb[3 * centre + 2], 0.32f, 1e-5f);
  EXPECT_NEAR(view.alpha[centre], 0.92f, 1e-5f);
  EXPECT_FLOAT_EQ(view.depth[centre], 4.0f);
  EXPECT_NEAR(view.expected_depth[centre], (0.6f * 4 + 0.32f * 6) / 0.92f, 1e-5f);
}

TEST(ReferenceRenderer, StopsBeforeTheTransmittanceCutoff) {
  // Eight Gaussians of opacity 0.8 on the axis: T = 0.2^k; the sixth would bring T to 6.4e-5 < 1e-4, so the
  // blending stops after five (alpha = 1 - 0.2^5); without the cut-off alpha would be 1 - 0.2^8.
  GaussianModel model;
  for (int k = 0; k < 8; ++k)
    model.AddConstantColor({0, 0, 3.0f + k}, Eigen::Vector3f::Constant(std::log(0.1f)),
                           Eigen::Quaternionf::Identity(), Logit(0.8f), {1, 1, 1});
  const RenderedView view = RenderReference(model, TestCamera(), RenderSettings());
  const std::size_t centre = 32 * 96 + 48;
  EXPECT_NEAR(view.alpha[centre], 1.0f - std::pow(0.2f, 5.0f), 1e-6f);
  EXPECT_NEAR(view.rgb[3 * centre], 1.0f - std::pow(0.2f, 5.0f), 1e-5f);
  EXPECT_FLOAT_EQ(view.depth[centre], 3.0f);
}

TEST(ReferenceRenderer, ShDegreeOneFollowsTheViewingDirection) {
  GaussianModel model;
  model.sh_degree = 1;
  // Coefficient-major: k = 0 (DC), 1 (-C1 y), 2 (C1 z), 3 (-C1 x); channel 0 gets distinct values.
  float sh[12] = {0.1f, 0, 0, 0.3f, 0, 0, -0.2f, 0, 0, 0.5f, 0, 0};
  const Eigen::Vector3f mu(1.0f, 0.5f, 5.0f);
  model.Add(mu, Eigen::Vector3f::Constant(std::log(0.1f)), Eigen::Quaternionf::Identity(), 0.0f, sh);
  const double C0 = 0.28209479177387814, C1 = 0.4886025119029199;
  for (const Eigen::Vector3d& centre : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, -1, 1)}) {
    const SE3 T_world_camera(SO3(), centre);
    const ProjectedGaussian g = ProjectGaussian(model, 0, MakeFloatCamera(TestCamera(T_world_camera)), {});
    ASSERT_FALSE(g.culled);
    const Eigen::Vector3d d = (mu.cast<double>() - centre).normalized();
    const double expected = C0 * 0.1 - C1 * d.y() * 0.3 + C1 * d.z() * -0.2 - C1 * d.x() * 0.5 + 0.5;
    EXPECT_NEAR(g.color.x(), std::max(0.0, expected), 1e-6);
    EXPECT_NEAR(g.color.y(), 0.5, 1e-6);  // zero coefficients: 0 + 0.5
  }
}

TEST(ReferenceRenderer, ShBasisIsOrthonormalUpToDegreeThree) {
  // The 3DGS basis is the real orthonormal SH basis: the integral over the sphere of Y_i Y_j is delta_ij.
  // Quadrature on a Fibonacci sphere of 20000 points (error ~1e-3).
  const int n = 20000;
  Eigen::Matrix<double, 16, 16> gram = Eigen::Matrix<double, 16, 16>::Zero();
  for (int s = 0; s < n; ++s) {
    const double z = 1.0 - (2.0 * s + 1.0) / n, r = std::sqrt(1 - z * z), phi = s * 2.399963229728653;
    const Eigen::Vector3f d(r * std::cos(phi), r * std::sin(phi), z);
    Eigen::Matrix<double, 16, 1> y;
    for (int k = 0; k < 16; ++k) {
      float coefficients[48] = {};
      coefficients[3 * k] = 1.0f;
      y[k] = EvaluateSh(3, coefficients, d).x();
    }
    gram += y * y.transpose() * (4.0 * M_PI / n);
  }
  EXPECT_LT((gram - Eigen::Matrix<double, 16, 16>::Identity()).cwiseAbs().maxCoeff(), 2e-3);
}

TEST(ReferenceRenderer, CullsBehindNearAndOffScreen) {
  GaussianModel model;
  const Eigen::Vector3f s = Eigen::Vector3f::Constant(std::log(0.05f));
  model.AddConstantColor({0, 0, -3}, s, Eigen::Quaternionf::Identity(), 0, {1, 1, 1});     // behind
  model.AddConstantColor({0, 0, 0.1f}, s, Eigen::Quaternionf::Identity(), 0, {1, 1, 1});   // before near 0.2
  model.AddConstantColor({-50, 0, 3}, s, Eigen::Quaternionf::Identity(), 0, {1, 1, 1});    // u = -1619 px
  model.AddConstantColor({0, 0, 0.25f}, s, Eigen::Quaternionf::Identity(), 0, {1, 1, 1});  // just past near
  const FloatCamera camera = MakeFloatCamera(TestCamera());
  EXPECT_TRUE(ProjectGaussian(model, 0, camera, {}).culled);
  EXPECT_TRUE(ProjectGaussian(model, 1, camera, {}).culled);
  EXPECT_TRUE(ProjectGaussian(model, 2, camera, {}).culled);
  EXPECT_FALSE(ProjectGaussian(model, 3, camera, {}).culled);
  model.positions.pop_back();
  model.log_scales.pop_back();
  model.rotations.pop_back();
  model.opacity_logits.pop_back();
  model.sh.resize(model.sh.size() - 3);
  const RenderedView view = RenderReference(model, TestCamera(), {});
  for (float a : view.alpha) ASSERT_EQ(a, 0.0f);
}

TEST(ReferenceRenderer, EwaCovarianceMatchesTheNumericJacobian) {
  // A rotated camera and an anisotropic, rotated Gaussian well inside the field of view (no clamping):
  // Sigma_2D = J_num Sigma J_num^T + 0.3 I with J_num the central-difference Jacobian of the pinhole
  // projection p_world -> (u, v), computed in double.
  const SE3 T_world_camera(SO3::Exp(Eigen::Vector3d(0.3, -0.2, 0.5)), Eigen::Vector3d(1, 2, -1));
  const SplatCamera camera = TestCamera(T_world_camera);
  const Eigen::Vector3d mu = T_world_camera * Eigen::Vector3d(0.4, -0.3, 4.0);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d scale(0.05, 0.2, 0.1);
  GaussianModel model;
  model.AddConstantColor(mu.cast<float>(), scale.array().log().cast<float>(), q.cast<float>(), 1.0f,
                         {1, 1, 1});
  const ProjectedGaussian g = ProjectGaussian(model, 0, MakeFloatCamera(camera), {});
  ASSERT_FALSE(g.culled);

  auto project = [&](const Eigen::Vector3d& p_world) {
    const Eigen::Vector3d t = T_world_camera.inverse() * p_world;
    const PinholeIntrinsics& k = camera.pinhole;
    return Eigen::Vector2d(k.fx * t.x() / t.z() + k.cx, k.fy * t.y() / t.z() + k.cy);
  };
  Eigen::Matrix<double, 2, 3> J;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d h = Eigen::Vector3d::Unit(a) * 1e-5;
    J.col(a) = (project(mu + h) - project(mu - h)) / 2e-5;
  }
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d sigma = R * scale.cwiseAbs2().asDiagonal() * R.transpose();
  const Eigen::Matrix2d sigma_2d = J * sigma * J.transpose() + 0.3 * Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d conic = sigma_2d.inverse();
  EXPECT_NEAR(g.mean_2d.x(), project(mu).x(), 1e-3);
  EXPECT_NEAR(g.mean_2d.y(), project(mu).y(), 1e-3);
  EXPECT_NEAR(g.conic.x(), conic(0, 0), 1e-4 * conic.norm());
  EXPECT_NEAR(g.conic.y(), conic(0, 1), 1e-4 * conic.norm());
  EXPECT_NEAR(g.conic.z(), conic(1, 1), 1e-4 * conic.norm());
  const double lambda_max = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(sigma_2d).eigenvalues().maxCoeff();
  EXPECT_EQ(g.radius, static_cast<int>(std::ceil(3 * std::sqrt(lambda_max))));
  EXPECT_NEAR(g.depth, 4.0, 1e-5);
}

}  // namespace
}  // namespace uf::splat
