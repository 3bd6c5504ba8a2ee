// The image metrics (PSNR, SSIM of splat/training/image_metrics.h) against hand-computed values, a closed
// form and a direct 2D-window implementation, and the photometric loss (splat/cpu_reference/
// photometric_loss.h) against hand values and its gradient against central finite differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "splat/cpu_reference/photometric_loss.h"
#include "splat/training/image_metrics.h"

namespace uf::splat {
namespace {

std::vector<float> RandomImage(std::mt19937_64& rng, int width, int height) {
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<float> image(3 * static_cast<std::size_t>(width) * height);
  for (float& v : image) v = uniform(rng);
  return image;
}

// The 1D Gaussian of the SSIM window written out independently: exp(-k^2 / 4.5), normalized over k = -5..5.
double Tap(int k) {
  double sum = 0;
  for (int j = -5; j <= 5; ++j) sum += std::exp(-j * j / 4.5);
  return std::exp(-k * k / 4.5) / sum;
}

// SSIM straight from the definition: the 2D window summed over in-image pixels (zero padding), no separation.
double DirectSsim(const std::vector<float>& a, const std::vector<float>& b, int width, int height) {
  double total = 0;
  for (int c = 0; c < 3; ++c)
    for (int py = 0; py < height; ++py)
      for (int px = 0; px < width; ++px) {
        double mx = 0, my = 0, mxx = 0, myy = 0, mxy = 0;
        for (int qy = std::max(0, py - 5); qy <= std::min(height - 1, py + 5); ++qy)
          for (int qx = std::max(0, px - 5); qx <= std::min(width - 1, px + 5); ++qx) {
            const double w = Tap(qx - px) * Tap(qy - py);
            const double x = a[3 * (qy * width + qx) + c], y = b[3 * (qy * width + qx) + c];
            mx += w * x, my += w * y, mxx += w * x * x, myy += w * y * y, mxy += w * x * y;
          }
        const double sx = mxx - mx * mx, sy = myy - my * my, sxy = mxy - mx * my;
        total += (2 * mx * my + 1e-4) * (2 * sxy + 9e-4) / ((mx * mx + my * my + 1e-4) * (sx + sy + 9e-4));
      }
  return total / (3.0 * width * height);
}

TEST(ImageMetrics, PsnrOfHandComputedImages) {
  const std::vector<float> a(12, 0.5f);
  std::vector<float> b = a;
  EXPECT_EQ(Psnr(a, b), std::numeric_limits<double>::infinity());
  b[4] = 0.6f;  // one of 12 entries off by 0.1: MSE = 0.01 / 12, PSNR = 10 log10(1200) = 30.7918 dB
  EXPECT_NEAR(Psnr(a, b), 30.791812, 1e-4);
  std::vector<float> c(12, 0.25f);  // every entry off by 0.25: 10 log10(16) = 12.0412 dB
  EXPECT_NEAR(Psnr(a, c), 12.041200, 1e-5);
}

TEST(ImageMetrics, SsimWindowIsTheNormalizedGaussian) {
  for (int k = -5; k <= 5; ++k) EXPECT_NEAR(SsimWindow()[k + 5], Tap(k), 1e-15);
  EXPECT_NEAR(SsimWindow()[5], 0.26601172486179436, 1e-15);  // the centre tap (3DGS' window)
}

TEST(ImageMetrics, SsimOfIdenticalImagesIsOne) {
  std::mt19937_64 rng(3);
  const std::vector<float> a = RandomImage(rng, 17, 12);
  EXPECT_NEAR(Ssim(a, a, 17, 12), 1.0, 1e-12);
}

// Constant images x = a, y = b: the window weight inside the image is w_p = W(px) W(py), W the sum of the
// in-image taps; then mu_x = a w, s_x = a^2 w - a^2 w^2 = a^2 w (1 - w), s_xy = a b w (1 - w), and
// S_p = (2 a b w^2 + C1)(2 a b w (1 - w) + C2) / (((a^2 + b^2) w^2 + C1)((a^2 + b^2) w (1 - w) + C2)).
// Away from the border (w = 1) this is the textbook (2 a b + C1) / (a^2 + b^2 + C1).
TEST(ImageMetrics, SsimOfConstantImagesMatchesTheClosedFormWithZeroPadding) {
  const int width = 24, height = 15;
  const double a = 0.6, b = 0.35;
  const std::vector<float> x(3 * width * height, static_cast<float>(a)),
      y(3 * width * height, static_cast<float>(b));
  const double fa = static_cast<float>(a), fb = static_cast<float>(b);
  auto inside = [](int p, int size) {
    double sum = 0;
    for (int k = -5; k <= 5; ++k) sum += (p + k >= 0 && p + k < size) ? Tap(k) : 0.0;
    return sum;
  };
  double expected = 0;
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      const double w = inside(px, width) * inside(py, height), ab = fa * fb, aa = fa * fa + fb * fb;
      expected += (2 * ab * w * w + 1e-4) * (2 * ab * w * (1 - w) + 9e-4) /
                  ((aa * w * w + 1e-4) * (aa * w * (1 - w) + 9e-4));
    }
  expected /= width * height;
  EXPECT_NEAR(Ssim(x, y, width, height), expected, 1e-9);
  // The interior value alone differs from the mean: padding matters (and is what 3DGS computes).
  const double interior = (2 * fa * fb + 1e-4) / (fa * fa + fb * fb + 1e-4);
  EXPECT_GT(std::abs(expected - interior), 1e-2);
}

TEST(ImageMetrics, SsimMatchesTheDirect2dWindowOnNoise) {
  std::mt19937_64 rng(5);
  const int width = 19, height = 14;
  const std::vector<float> a = RandomImage(rng, width, height);
  std::vector<float> b = RandomImage(rng, width, height);
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = 0.6f * a[i] + 0.4f * b[i];  // correlated: SSIM ~ 0.7
  const double ssim = Ssim(a, b, width, height);
  EXPECT_NEAR(ssim, DirectSsim(a, b, width, height), 1e-12);
  EXPECT_GT(ssim, 0.3);
  EXPECT_LT(ssim, 0.95);
}

// A random rendered view with every kind of pixel: alpha below 1e-4 (no expected depth), no target depth,
// and valid depth pairs; ties |r - t| and |E - d| are kept far from 0 so that finite differences are smooth.
struct LossCase {
  RenderedView rendered;
  std::vector<float> target_rgb, target_depth;
};

LossCase RandomLossCase(std::uint64_t seed, int width, int height) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  LossCase c;
  c.rendered = RenderedView::Sized(width, height);
  c.rendered.rgb = RandomImage(rng, width, height);
  for (std::size_t i = 0; i < c.rendered.rgb.size(); ++i) {
    float t = 0.5f * c.rendered.rgb[i] + 0.5f * uniform(rng);
    if (std::abs(t - c.rendered.rgb[i]) < 0.02f) t = c.rendered.rgb[i] + (t < 0.5f ? 0.05f : -0.05f);
    c.target_rgb.push_back(t);
  }
  for (int p = 0; p < width * height; ++p) {
    const float alpha = p % 11 == 3 ? 5e-5f : 0.05f + 0.95f * uniform(rng);
    const float E = 1.0f + 20.0f * uniform(rng);
    c.rendered.alpha[p] = alpha;
    c.rendered.expected_depth[p] = alpha < 1e-4f ? RenderedView::kNoDepth : E;
    c.rendered.depth[p] = E;
    c.target_depth.push_back(p % 4 == 1 ? 0.0f
                                        : E + (uniform(rng) < 0.5f ? -1.0f : 1.0f) * (0.5f + uniform(rng)));
  }
  return c;
}

TEST(PhotometricLoss, TermsOfAHandCase) {
  // 12 x 12 pixels, rendered 0.5 everywhere, target 0.25: L1 = 0.25; SSIM of the constant pair from the
  // closed form (checked above), D-SSIM = 1 - Ssim; depth: one valid pixel with |E - d| / d = 2 / 6.
  const int n = 12;
  RenderedView rendered = RenderedView::Sized(n, n);
  std::fill(rendered.rgb.begin(), rendered.rgb.end(), 0.5f);
  std::fill(rendered.alpha.begin(), rendered.alpha.end(), 0.5f);
  std::fill(rendered.expected_depth.begin(), rendered.expected_depth.end(), 4.0f);
  const std::vector<float> target(3 * n * n, 0.25f);
  std::vector<float> depth(n * n, 0.0f);
  depth[7] = 6.0f;
  const PhotometricLoss loss = EvaluatePhotometricLoss(rendered, target, depth, {0.2f, 0.5f});
  EXPECT_NEAR(loss.l1, 0.25, 1e-12);
  EXPECT_NEAR(loss.dssim, 1.0 - Ssim(rendered.rgb, target, n, n), 1e-12);
  EXPECT_NEAR(loss.depth, 2.0 / 6.0, 1e-7);
  EXPECT_NEAR(loss.total, 0.8 * 0.25 + 0.2 * loss.dssim + 0.5 * 2.0 / 6.0, 1e-7);  // weights are floats
  // E = D / alpha below d: dL/dE = -0.5 / (d 1) (one pixel) = -1 / 12; dL/dD = dL/dE / alpha = -1 / 6,
  // dL/dalpha = -dL/dE E / alpha = 2 / 3.
  EXPECT_FLOAT_EQ(loss.gradients.depth_sum[7], -1.0f / 6.0f);
  EXPECT_FLOAT_EQ(loss.gradients.alpha[7], 2.0f / 3.0f);
  EXPECT_EQ(loss.gradients.depth_sum[8], 0.0f);
  // No depth target: no term and no depth gradient.
  const PhotometricLoss no_depth = EvaluatePhotometricLoss(rendered, target, {}, {0.2f, 0.5f});
  EXPECT_EQ(no_depth.depth, 0.0);
  EXPECT_EQ(no_depth.gradients.alpha, std::vector<float>(n * n, 0.0f));
  EXPECT_EQ(no_depth.gradients.depth_sum, std::vector<float>(n * n, 0.0f));
}

// Central differences of the double-valued total against the analytic float gradient. The step is taken on
// float inputs: the actual step (x + h) - (x - h) in float is used as the denominator, so input rounding does
// not enter; the truncation error h^2 L''' / 6 is ~1e-6 of the gradient scale at h = 1e-3.
TEST(PhotometricLoss, GradientMatchesFiniteDifferences) {
  const int width = 13, height = 9;
  for (const PhotometricLossWeights weights :
       {PhotometricLossWeights{0.2f, 0.3f}, PhotometricLossWeights{1.0f, 0.0f}}) {
    LossCase c = RandomLossCase(7, width, height);
    const PhotometricLoss loss = EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights);
    auto total = [&] {
      return EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights).total;
    };
    // Perturbs *value by +-h and returns the central difference.
    auto numeric = [&](float* value, float h) {
      const float saved = *value;
      *value = saved + h;
      const float up = *value;
      const double plus = total();
      *value = saved - h;
      const float down = *value;
      const double minus = total();
      *value = saved;
      return (plus - minus) / (static_cast<double>(up) - down);
    };
    double scale = 0, error = 0;
    for (std::size_t i = 0; i < c.rendered.rgb.size(); ++i) {
      const double fd = numeric(&c.rendered.rgb[i], 1e-3f);
      scale = std::max(scale, std::abs(fd));
      error = std::max(error, std::abs(fd - loss.gradients.rgb[i]));
    }
    EXPECT_LT(error, 1e-4 * scale) << "rgb, ssim weight " << weights.ssim_weight;
    // Depth sum D = E alpha and alpha (E follows both): perturb them and recompute E = D / alpha.
    int checked = 0;
    for (int p = 0; p < width * height; ++p) {
      const float alpha = c.rendered.alpha[p];
      if (alpha < 1e-4f) {  // no expected depth: no gradient
        EXPECT_EQ(loss.gradients.depth_sum[p], 0.0f);
        EXPECT_EQ(loss.gradients.alpha[p], 0.0f);
        continue;
      }
      double D = static_cast<double>(c.rendered.expected_depth[p]) * alpha;
      auto total_at = [&](double d_sum, double a) {
        c.rendered.expected_depth[p] = static_cast<float>(d_sum / a);
        c.rendered.alpha[p] = static_cast<float>(a);
        const double value = total();
        c.rendered.expected_depth[p] = static_cast<float>(D / alpha);
        c.rendered.alpha[p] = alpha;
        return value;
      };
      const double h = 1e-3 * D;
      const double fd_D = (total_at(D + h, alpha) - total_at(D - h, alpha)) / (2 * h);
      const double fd_alpha = (total_at(D, alpha + 1e-4) - total_at(D, alpha - 1e-4)) / 2e-4;
      const double tolerance =
          1e-3 * std::abs(weights.depth_weight) / alpha * (1.0 + std::abs(D) / alpha) + 1e-9;
      EXPECT_NEAR(loss.gradients.depth_sum[p], fd_D, tolerance) << "pixel " << p;
      EXPECT_NEAR(loss.gradients.alpha[p], fd_alpha, tolerance) << "pixel " << p;
      checked += loss.gradients.depth_sum[p] != 0;
    }
    if (weights.depth_weight > 0) {
      EXPECT_GT(checked, width * height / 2);
    }
  }
}

// Masked pixels count as rendered perfectly: the loss is that of the render with the target pasted into the
// masked pixels, whatever the render holds there, and their gradient is 0; the other pixels' gradient still
// matches finite differences.
TEST(PhotometricLoss, MaskedPixelsCountAsRenderedPerfectly) {
  const int width = 13, height = 9;
  LossCase c = RandomLossCase(8, width, height);
  std::vector<std::uint8_t> mask(width * height, 1);
  for (int p = 0; p < width * height; p += 4) mask[p] = 0;
  const PhotometricLossWeights weights{0.2f, 0.3f};
  const PhotometricLoss loss =
      EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights, mask);
  RenderedView pasted = c.rendered;
  std::vector<float> depth = c.target_depth;
  for (int p = 0; p < width * height; ++p)
    if (mask[p] == 0) {
      for (int k = 0; k < 3; ++k) pasted.rgb[3 * p + k] = c.target_rgb[3 * p + k];
      depth[p] = 0;  // no depth pair
    }
  const PhotometricLoss expected = EvaluatePhotometricLoss(pasted, c.target_rgb, depth, weights);
  EXPECT_NEAR(loss.total, expected.total, 1e-12);
  EXPECT_NEAR(loss.dssim, expected.dssim, 1e-12);
  EXPECT_NEAR(loss.depth, expected.depth, 1e-12);
  EXPECT_LT(loss.total, EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights).total);
  double scale = 0, error = 0;
  for (int p = 0; p < width * height; ++p) {
    const bool masked = mask[p] == 0;
    for (int k = 0; k < 3; ++k) {
      if (masked) {
        EXPECT_EQ(loss.gradients.rgb[3 * p + k], 0.0f);
        continue;
      }
      // Unmasked: central difference of the masked loss.
      float& value = c.rendered.rgb[3 * p + k];
      const float saved = value;
      value = saved + 1e-3f;
      const float up = value;
      const double plus =
          EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights, mask).total;
      value = saved - 1e-3f;
      const float down = value;
      const double minus =
          EvaluatePhotometricLoss(c.rendered, c.target_rgb, c.target_depth, weights, mask).total;
      value = saved;
      const double fd = (plus - minus) / (static_cast<double>(up) - down);
      scale = std::max(scale, std::abs(fd));
      error = std::max(error, std::abs(fd - loss.gradients.rgb[3 * p + k]));
    }
    if (masked) {
      EXPECT_EQ(loss.gradients.depth_sum[p], 0.0f);
      EXPECT_EQ(loss.gradients.alpha[p], 0.0f);
    }
  }
  EXPECT_LT(error, 1e-4 * scale);  // as GradientMatchesFiniteDifferences
}

TEST(ImageMetrics, PsnrOverTheUnmaskedPixels) {
  // Two pixels: equal in the first, 0.1 apart in every channel of the second. Unmasked: MSE 0.005 (23.0 dB);
  // the second masked: identical (inf); the first masked: MSE 0.01, 20 dB.
  const std::vector<float> a = {0.5f, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f}, b = {0.5f, 0.5f, 0.5f, 0.3f, 0.3f, 0.3f};
  EXPECT_NEAR(Psnr(a, b), 10 * std::log10(1 / 0.005), 1e-4);
  const std::vector<std::uint8_t> second = {1, 0}, first = {0, 1};
  EXPECT_TRUE(std::isinf(Psnr(a, b, second)));
  EXPECT_NEAR(Psnr(a, b, first), 20.0, 1e-4);
}

}  // namespace
}  // namespace uf::splat
