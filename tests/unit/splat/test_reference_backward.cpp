// CPU reference backward: every gradient entry of random small scenes against central finite differences of
// the forward reference renderer (RenderReference), for a random linear loss on rgb, alpha and the depth sum
// D, and for a loss on the expected depth.
//
// The forward is float, so the finite differences are float too; they are made reliable by:
//  - summing the loss in double and dividing by the step actually taken, (float)(x + h) - (float)(x - h);
//  - steps h of 2e-3 (5e-4, see below) on parameters of order 1 (positions in m at 2-4 m, log-scales,
//    quaternion components, logits, SH coefficients): the rounding noise of the loss (~1e-6 over a few
//    hundred touched pixels) gives an error ~1e-6 / 2h, and the truncation error (h^2 f''' / 6) is smaller
//    still, so the tolerance is 2e-3 + 1e-2 |g| (measured: the largest error is 0.2 of it with h = 2e-3,
//    0.65 of it with h = 5e-4, and the error grows to 1-1.6 of it with h = 1e-4, the noise floor);
//  - scenes built away from the clamps: opacities <= 0.82 so alpha < max_alpha = 0.99, few enough
//    overlapping Gaussians that the transmittance cut-off is rarely reached; the remaining discontinuities
//    (a pixel crossing min_alpha unless it is set to 0, a tile rectangle or the cut-off changing within
//    the step) are detected
//    by comparing the difference quotients with steps h and 2h: where they disagree by more than the
//    tolerance the entry straddles a discontinuity and is not compared; the tests require that nearly all
//    entries are compared.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <tuple>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/cpu_reference/reference_renderer.h"

namespace uf::splat {
namespace {

constexpr int kWidth = 24, kHeight = 16;

SplatCamera TestCamera() {
  SplatCamera camera;
  camera.pinhole = {.width = kWidth, .height = kHeight, .fx = 20, .fy = 21, .cx = 11.3, .cy = 7.6};
  camera.T_world_camera = SE3(SO3::Exp(Eigen::Vector3d(0.05, -0.1, 0.08)), Eigen::Vector3d(0.3, -0.2, 0.1));
  return camera;
}

// `count` Gaussians in front of the camera (2-4 m), projected sigma ~1-3 px, random unnormalized rotations,
// opacity in [0.18, 0.82], SH colours mostly in [0.2, 0.8]; Gaussian 0 lies beyond the 1.3 x half-fov clamp
// of J (t_x / t_z = 0.9 > 1.3 * 0.6) and is large enough to reach into the image; Gaussian 1 has a
// negative red channel (clamped to 0).
GaussianModel RandomScene(std::uint64_t seed, int count, int sh_degree) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  const SplatCamera camera = TestCamera();
  GaussianModel model;
  model.sh_degree = sh_degree;
  std::vector<float> sh(model.ShStride());
  for (int i = 0; i < count; ++i) {
    const float z = 2.0f + 2.0f * uniform(rng);
    Eigen::Vector3d t_camera(z * (1.2f * uniform(rng) - 0.6f), z * (0.8f * uniform(rng) - 0.4f), z);
    Eigen::Vector3f log_scale(std::log(0.1f + 0.3f * uniform(rng)), std::log(0.1f + 0.3f * uniform(rng)),
                              std::log(0.1f + 0.3f * uniform(rng)));
    if (i == 0) {
      t_camera = Eigen::Vector3d(0.9 * 2.5, 0.1, 2.5);
      log_scale = Eigen::Vector3f(std::log(0.5f), std::log(0.4f), std::log(0.3f));
    }
    const Eigen::Vector3f position = (camera.T_world_camera * t_camera).cast<float>();
    const Eigen::Quaternionf rotation(normal(rng), normal(rng), normal(rng), normal(rng));
    for (int k = 0; k < model.ShStride(); ++k) sh[k] = (k < 3 ? 1.0f : 0.3f) * normal(rng);
    for (int c = 0; c < 3; ++c) sh[c] = (0.2f + 0.6f * uniform(rng) - 0.5f) / kShC0;
    if (i == 1) sh[0] = (-0.3f - 0.5f) / kShC0;
    model.Add(position, log_scale, rotation, 3.0f * uniform(rng) - 1.5f, sh.data());
  }
  return model;
}

// The loss weights: L = sum_p w_rgb . rgb_p + w_alpha alpha_p + w_D D_p (+ w_E E_p on `depth_mask`).
struct LinearLoss {
  ViewGradients weights;
  std::vector<float> expected_depth_weights;  // empty: no expected-depth term
};

double Loss(const RenderedView& view, const LinearLoss& loss) {
  double sum = 0;
  for (std::size_t p = 0; p < view.alpha.size(); ++p) {
    for (int c = 0; c < 3; ++c) sum += double(loss.weights.rgb[3 * p + c]) * view.rgb[3 * p + c];
    sum += double(loss.weights.alpha[p]) * view.alpha[p];
    const bool has_depth = std::isfinite(view.expected_depth[p]);
    // D = E * alpha where E is defined; where it is not, alpha < 1e-4 and D < 1e-4 t_z ~ 0.
    if (has_depth) sum += double(loss.weights.depth_sum[p]) * view.expected_depth[p] * view.alpha[p];
    if (!loss.expected_depth_weights.empty() && loss.expected_depth_weights[p] != 0.0f)
      sum += double(loss.expected_depth_weights[p]) * view.expected_depth[p];
  }
  return sum;
}

// The scalar parameters of Gaussian i: 3 position, 3 log-scale, 4 rotation (w x y z), 1 logit, then SH.
int ParameterCount(const GaussianModel& model) { return 11 + model.ShStride(); }

float& Parameter(GaussianModel& model, std::size_t i, int k) {
  if (k < 3) return model.positions[i][k];
  if (k < 6) return model.log_scales[i][k - 3];
  if (k == 6) return model.rotations[i].w();
  if (k < 10) return model.rotations[i].coeffs()[k - 7];  // Eigen stores (x, y, z, w)
  if (k == 10) return model.opacity_logits[i];
  return model.sh[i * model.ShStride() + (k - 11)];
}

float Gradient(const GaussianGradients& g, const GaussianModel& model, std::size_t i, int k) {
  if (k < 3) return g.position[i][k];
  if (k < 6) return g.log_scale[i][k - 3];
  if (k < 10) return g.rotation[i][k - 6];
  if (k == 10) return g.opacity_logit[i];
  return g.sh[i * model.ShStride() + (k - 11)];
}

// Central difference of the loss along parameter (i, k) with step h, divided by the step actually taken.
double FiniteDifference(const GaussianModel& model, const SplatCamera& camera, const RenderSettings& settings,
                        const LinearLoss& loss, std::size_t i, int k, float h) {
  GaussianModel plus = model, minus = model;
  Parameter(plus, i, k) += h;
  Parameter(minus, i, k) -= h;
  const double step = double(Parameter(plus, i, k)) - double(Parameter(minus, i, k));
  return (Loss(RenderReference(plus, camera, settings), loss) -
          Loss(RenderReference(minus, camera, settings), loss)) /
         step;
}

struct Comparison {
  int compared = 0, skipped = 0, nonzero = 0;
  double max_error = 0;
};

Comparison CompareAll(const GaussianModel& model, const SplatCamera& camera, const RenderSettings& settings,
                      const LinearLoss& loss, const GaussianGradients& analytic, float step) {
  Comparison result;
  for (std::size_t i = 0; i < model.size(); ++i) {
    for (int k = 0; k < ParameterCount(model); ++k) {
      const double fd = FiniteDifference(model, camera, settings, loss, i, k, step);
      const double fd2 = FiniteDifference(model, camera, settings, loss, i, k, 2 * step);
      const double tolerance = 2e-3 + 1e-2 * std::abs(fd);
      if (std::abs(fd - fd2) > tolerance) {
        ++result.skipped;  // a discontinuity within the step
        continue;
      }
      const double g = Gradient(analytic, model, i, k);
      ++result.compared;
      if (std::abs(g) > 1e-2) ++result.nonzero;
      result.max_error = std::max(result.max_error, std::abs(g - fd) / (2e-3 + 1e-2 * std::abs(fd)));
      EXPECT_NEAR(g, fd, tolerance) << "Gaussian " << i << " parameter " << k << " (fd with 2h: " << fd2
                                    << ")";
    }
  }
  return result;
}

LinearLoss RandomLoss(std::uint64_t seed, bool with_alpha_and_depth) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> weight(-1.0f, 1.0f);
  const std::size_t pixels = kWidth * kHeight;
  LinearLoss loss;
  loss.weights.rgb.resize(3 * pixels);
  for (float& w : loss.weights.rgb) w = weight(rng);
  loss.weights.alpha.assign(pixels, 0.0f);
  loss.weights.depth_sum.assign(pixels, 0.0f);
  if (with_alpha_and_depth) {
    for (float& w : loss.weights.alpha) w = weight(rng);
    for (float& w : loss.weights.depth_sum) w = 0.3f * weight(rng);
  }
  return loss;
}

// Parameter: (SH degree, min_alpha as in the default settings). With min_alpha = 0 no pixel is ever
// skipped, which removes the most frequent discontinuity (a pixel of a Gaussian's tail crossing
// min_alpha), so the step can be 2e-3 and no entry is expected to straddle one; with the default
// min_alpha = 1/255 the step is 5e-4 (rounding error ~1e-6 / 1e-3 ~ 1e-3, still within the tolerance),
// which makes crossings rare enough (measured: at most 4% of the entries) for the h / 2h check to catch.
// Required: 98% of the entries compared with min_alpha = 0 (measured: all), 90% with the default.
class BackwardAgainstFiniteDifferences : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(BackwardAgainstFiniteDifferences, EveryParameterOfARandomScene) {
  const auto [sh_degree, default_min_alpha] = GetParam();
  const SplatCamera camera = TestCamera();
  RenderSettings settings;
  settings.background = Eigen::Vector3f(0.2f, 0.5f, 0.9f);
  if (!default_min_alpha) settings.min_alpha = 0.0f;
  const GaussianModel model = RandomScene(100 + sh_degree, 12, sh_degree);
  const LinearLoss loss = RandomLoss(200 + sh_degree, /*with_alpha_and_depth=*/sh_degree % 2 == 1);
  const GaussianGradients analytic = RenderReferenceBackward(model, camera, settings, loss.weights);
  const Comparison c = CompareAll(model, camera, settings, loss, analytic, default_min_alpha ? 5e-4f : 2e-3f);
  const int total = c.compared + c.skipped;
  EXPECT_GE(c.compared, (default_min_alpha ? 0.9 : 0.98) * total)
      << c.skipped << " of " << total << " entries straddle a discontinuity";
  EXPECT_GE(c.nonzero, total / 2) << "too few non-zero gradients: the scene does not exercise the backward";
  RecordProperty("max_error_over_tolerance", std::to_string(c.max_error));
  RecordProperty("skipped", std::to_string(c.skipped) + " of " + std::to_string(total));
}

INSTANTIATE_TEST_SUITE_P(ShDegreesAndMinAlpha, BackwardAgainstFiniteDifferences,
                         ::testing::Combine(::testing::Values(0, 1, 2, 3), ::testing::Bool()));

// The Gaussian beyond the J clamp and the clamped colour channel are in every scene; check they matter.
TEST(BackwardAgainstFiniteDifferences, ClampedJacobianAndClampedColourAreExercised) {
  const SplatCamera camera = TestCamera();
  const GaussianModel model = RandomScene(101, 12, 1);
  const LinearLoss loss = RandomLoss(201, true);
  const GaussianGradients g = RenderReferenceBackward(model, camera, RenderSettings(), loss.weights);
  EXPECT_GT(g.log_scale[0].norm(), 1e-3f);  // Gaussian 0 is rendered though its mean is off-screen
  EXPECT_GT(g.position[0].norm(), 1e-3f);
  EXPECT_EQ(g.sh[1 * model.ShStride() + 0], 0.0f);  // red of Gaussian 1 clamped at 0: no gradient
  EXPECT_NE(g.sh[1 * model.ShStride() + 1], 0.0f);
}

// L = sum w_E E_p over pixels well covered, through AddExpectedDepthGradient. alpha > 0.3 keeps E defined
// within the steps and bounds the amplification of rounding noise by 1 / alpha in E = D / alpha.
TEST(BackwardAgainstFiniteDifferences, ExpectedDepthLoss) {
  const SplatCamera camera = TestCamera();
  RenderSettings settings;
  settings.min_alpha = 0.0f;  // as above: no min_alpha crossings
  const GaussianModel model = RandomScene(7, 10, 0);
  const RenderedView forward = RenderReference(model, camera, settings);
  LinearLoss loss = RandomLoss(8, false);
  for (float& w : loss.weights.rgb) w = 0.0f;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> weight(-1.0f, 1.0f);
  loss.expected_depth_weights.assign(forward.alpha.size(), 0.0f);
  int covered = 0;
  for (std::size_t p = 0; p < forward.alpha.size(); ++p)
    if (forward.alpha[p] > 0.3f) loss.expected_depth_weights[p] = weight(rng), ++covered;
  ASSERT_GT(covered, 30);
  ViewGradients image_gradients = loss.weights;
  image_gradients.alpha.clear();
  image_gradients.depth_sum.clear();
  AddExpectedDepthGradient(forward, loss.expected_depth_weights, &image_gradients);
  const GaussianGradients analytic = RenderReferenceBackward(model, camera, settings, image_gradients);
  const Comparison c = CompareAll(model, camera, settings, loss, analytic, 2e-3f);
  EXPECT_GE(c.compared, 0.95 * (c.compared + c.skipped));
  EXPECT_GE(c.nonzero, 20);
}

}  // namespace
}  // namespace uf::splat
