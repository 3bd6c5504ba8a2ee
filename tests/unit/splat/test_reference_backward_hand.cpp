// CPU reference backward, hand-derived cases: two Gaussians blended into one pixel (against a closed form
// in double), one axis-aligned Gaussian seen head-on (gradients written out by hand), the max_alpha clamp,
// the expected-depth conversion and the SH gradients.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/cpu_reference/spherical_harmonics.h"
#include "splat/cpu_reference/spherical_harmonics_backward.h"

namespace uf::splat {
namespace {

// Two Gaussians over pixel (0, 0), front to back, closed form (rule 4 with nothing skipped):
//   rgb = a1 c1 + (1 - a1) a2 c2 + (1 - a1)(1 - a2) bg,  A = 1 - (1 - a1)(1 - a2),  D = a1 z1 + (1 - a1) a2
//   z2, a_i = o_i exp(-0.5 (A_i dx^2 + C_i dy^2) - B_i dx dy), (dx, dy) = -(u_i, v_i).
// Parameters per Gaussian: u, v, A, B, C, depth, r, g, b, opacity (10).
double TwoGaussianLoss(const double p[20], const Eigen::Vector3d& bg, const Eigen::Vector3d& w_rgb,
                       double w_A, double w_D) {
  double a[2];
  Eigen::Vector3d c[2];
  for (int i = 0; i < 2; ++i) {
    const double* q = p + 10 * i;
    const double dx = -q[0], dy = -q[1];
    a[i] = q[9] * std::exp(-0.5 * (q[2] * dx * dx + q[4] * dy * dy) - q[3] * dx * dy);
    c[i] = Eigen::Vector3d(q[6], q[7], q[8]);
  }
  const Eigen::Vector3d rgb = a[0] * c[0] + (1 - a[0]) * a[1] * c[1] + (1 - a[0]) * (1 - a[1]) * bg;
  const double A = 1 - (1 - a[0]) * (1 - a[1]);
  const double D = a[0] * p[5] + (1 - a[0]) * a[1] * p[15];
  return w_rgb.dot(rgb) + w_A * A + w_D * D;
}

TEST(BackwardByHand, TwoGaussiansInOnePixelMatchTheClosedForm) {
  const double p[20] = {0.3,  -0.2, 0.5, 0.1,   0.4, 2.0, 0.9, 0.2, 0.1, 0.6,  //
                        -0.5, 0.4,  0.3, -0.05, 0.6, 3.0, 0.1, 0.7, 0.3, 0.5};
  const Eigen::Vector3d bg(0.2, 0.3, 0.4), w_rgb(0.7, -0.4, 0.25);
  const double w_A = -0.6, w_D = 0.35;
  std::vector<ProjectedGaussian> projected(2);
  for (int i = 0; i < 2; ++i) {
    const double* q = p + 10 * i;
    ProjectedGaussian& g = projected[i];
    g.culled = false;
    g.mean_2d = Eigen::Vector2d(q[0], q[1]).cast<float>();
    g.conic = Eigen::Vector3d(q[2], q[3], q[4]).cast<float>();
    g.radius = 3;
    g.depth = static_cast<float>(q[5]);
    g.color = Eigen::Vector3d(q[6], q[7], q[8]).cast<float>();
    g.opacity = static_cast<float>(q[9]);
    g.tile_min = {0, 0};
    g.tile_max = {1, 1};
  }
  FloatCamera camera{};
  camera.width = camera.height = camera.tiles_x = camera.tiles_y = 1;
  RenderSettings settings;
  settings.background = bg.cast<float>();
  const ViewGradients weights{{0.7f, -0.4f, 0.25f}, {-0.6f}, {0.35f}};
  const std::vector<ProjectedGaussianGradients> v =
      RasterizeReferenceBackward(projected, camera, settings, weights);

  // Central differences of the closed form in double (h = 1e-6: error ~1e-10).
  double expected[20];
  for (int k = 0; k < 20; ++k) {
    double plus[20], minus[20];
    std::copy(p, p + 20, plus);
    std::copy(p, p + 20, minus);
    plus[k] += 1e-6;
    minus[k] -= 1e-6;
    expected[k] =
        (TwoGaussianLoss(plus, bg, w_rgb, w_A, w_D) - TwoGaussianLoss(minus, bg, w_rgb, w_A, w_D)) / 2e-6;
  }
  for (int i = 0; i < 2; ++i) {
    const double* e = expected + 10 * i;
    const ProjectedGaussianGradients& g = v[i];
    const double got[10] = {g.mean_2d.x(), g.mean_2d.y(), g.conic.x(), g.conic.y(), g.conic.z(),
                            g.depth,       g.color.x(),   g.color.y(), g.color.z(), g.opacity};
    for (int k = 0; k < 10; ++k) EXPECT_NEAR(got[k], e[k], 1e-5 + 1e-5 * std::abs(e[k])) << i << " " << k;
  }
}

// One Gaussian at t = (0, 0, z) seen head-on by an identity camera, R = I, scales (sx, sy, sz): there
// J = [[f/z, 0, 0], [0, f/z, 0]] and dJ/dt_x, dJ/dt_y do not change Sigma_2D at t_x = t_y = 0, so
//   Sigma_2D = diag((f sx / z)^2 + 0.3, (f sy / z)^2 + 0.3) =: diag(X, Y),  u = cx, v = cy,
//   a = o exp(-0.5 (dx^2 / X + dy^2 / Y)),  red = a c  at pixel (cx + dx, cy + dy) on a black background:
//   d red/d logit = c a (1 - o),  d red/d f_dc,r = Y_0 a,
//   d red/d mu_x = c a (dx / X) f / z,  d red/d mu_y = c a (dy / Y) f / z,
//   d red/d mu_z = c a (0.5 dx^2 / X^2 dX/dz + 0.5 dy^2 / Y^2 dY/dz),  dX/dz = -2 f^2 sx^2 / z^3,
//   d red/d ln sx = c a 0.5 dx^2 / X^2 2 (f sx / z)^2  (likewise y),  d red/d ln sz = 0.
struct HeadOn {
  SplatCamera camera;
  GaussianModel model;
  static constexpr float f = 20, z = 2, sx = 0.2f, sy = 0.15f, sz = 0.3f, red = 0.7f;
  HeadOn(float logit) {
    camera.pinhole = {.width = 16, .height = 16, .fx = f, .fy = f, .cx = 8, .cy = 8};
    model.AddConstantColor({0, 0, z}, {std::log(sx), std::log(sy), std::log(sz)},
                           Eigen::Quaternionf(2, 0, 0, 0), logit, {red, 0.4f, 0.1f});
  }
  GaussianGradients RedAt(int x, int y) const {
    ViewGradients w;
    w.rgb.assign(3 * 16 * 16, 0.0f);
    w.rgb[3 * (y * 16 + x)] = 1.0f;
    return RenderReferenceBackward(model, camera, RenderSettings(), w);
  }
};

TEST(BackwardByHand, SingleGaussianHeadOn) {
  const HeadOn scene(0.4f);
  const double dx = 2, dy = -1, f = HeadOn::f, z = HeadOn::z, c = HeadOn::red;
  const double o = 1 / (1 + std::exp(-0.4));
  const double fx = f * HeadOn::sx / z, fy = f * HeadOn::sy / z;
  const double X = fx * fx + 0.3, Y = fy * fy + 0.3;
  const double a = o * std::exp(-0.5 * (dx * dx / X + dy * dy / Y));
  const GaussianGradients g = scene.RedAt(10, 7);
  auto near = [](double got, double want) { EXPECT_NEAR(got, want, 1e-6 + 2e-4 * std::abs(want)); };
  near(g.opacity_logit[0], c * a * (1 - o));
  near(g.sh[0], kShC0 * a);
  near(g.sh[1], 0.0);
  near(g.position[0].x(), c * a * dx / X * f / z);
  near(g.position[0].y(), c * a * dy / Y * f / z);
  const double dX_dz = -2 * fx * fx / z, dY_dz = -2 * fy * fy / z;
  near(g.position[0].z(), c * a * 0.5 * (dx * dx / (X * X) * dX_dz + dy * dy / (Y * Y) * dY_dz));
  near(g.log_scale[0].x(), c * a * dx * dx / (X * X) * fx * fx);
  near(g.log_scale[0].y(), c * a * dy * dy / (Y * Y) * fy * fy);
  near(g.log_scale[0].z(), 0.0);
  near(g.mean_2d[0].x(), c * a * dx / X);
  // Scaling the stored quaternion changes nothing: its gradient is orthogonal to it (here q = (2, 0, 0, 0)).
  near(g.rotation[0][0], 0.0);
}

TEST(BackwardByHand, NoGradientThroughTheMaxAlphaClamp) {
  const HeadOn scene(8.0f);  // opacity 0.99966 > max_alpha at the centre pixel
  const GaussianGradients g = scene.RedAt(8, 8);
  EXPECT_EQ(g.opacity_logit[0], 0.0f);
  EXPECT_EQ(g.position[0].norm(), 0.0f);
  EXPECT_EQ(g.log_scale[0].norm(), 0.0f);
  EXPECT_NEAR(g.sh[0], kShC0 * 0.99f, 1e-6f);  // the colour still gets T a = max_alpha
}

TEST(BackwardByHand, ExpectedDepthToDepthSumAndAlpha) {
  RenderedView view;
  view.width = 2;
  view.height = 1;
  view.alpha = {0.5f, 0.0f};
  view.expected_depth = {3.0f, RenderedView::kNoDepth};
  ViewGradients g;
  AddExpectedDepthGradient(view, {1.0f, 1.0f}, &g);
  // E = D / A = 3 with A = 0.5: dE/dD = 1 / A = 2, dE/dA = -E / A = -6; no depth, no gradient.
  ASSERT_EQ(g.depth_sum.size(), 2u);
  EXPECT_FLOAT_EQ(g.depth_sum[0], 2.0f);
  EXPECT_FLOAT_EQ(g.alpha[0], -6.0f);
  EXPECT_EQ(g.depth_sum[1], 0.0f);
  EXPECT_EQ(g.alpha[1], 0.0f);
}

TEST(BackwardByHand, ShGradientsMatchEvaluateSh) {
  std::mt19937_64 rng(5);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  float coefficients[48], gradients[48] = {};
  for (float& c : coefficients) c = normal(rng);
  const Eigen::Vector3f d = Eigen::Vector3f(0.3f, -0.5f, 0.8f).normalized();
  const Eigen::Vector3f w(0.6f, -0.8f, 0.3f);
  const Eigen::Vector3f dL_dd = ShBackward(3, coefficients, d, w, gradients);
  // Coefficients: L is linear in them, dL/dc_kc = w_c Y_k(d) = L with only c_kc = 1.
  for (int k = 0; k < 48; ++k) {
    float unit[48] = {};
    unit[k] = 1.0f;
    EXPECT_NEAR(gradients[k], w.dot(EvaluateSh(3, unit, d)), 1e-6f) << k;
  }
  // Direction: central differences of the polynomial (float, h = 1e-3: error ~1e-4).
  for (int j = 0; j < 3; ++j) {
    Eigen::Vector3f plus = d, minus = d;
    plus[j] += 1e-3f;
    minus[j] -= 1e-3f;
    const float fd =
        w.dot(EvaluateSh(3, coefficients, plus) - EvaluateSh(3, coefficients, minus)) / (plus[j] - minus[j]);
    EXPECT_NEAR(dL_dd[j], fd, 2e-3f * (1 + std::abs(fd))) << j;
  }
}

}  // namespace
}  // namespace uf::splat
