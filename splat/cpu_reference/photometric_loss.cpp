#include "splat/cpu_reference/photometric_loss.h"

#include <cassert>
#include <cmath>
#include <cstddef>

#include "splat/training/image_metrics.h"

namespace uf::splat {

namespace {

double Sign(double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }

// Adds d(sum over pixels of S)/dx for one channel, scaled by `scale`, to gradient[3 q + channel].
//
// Derivation. With the window moments of channel images x (rendered) and y (target) at pixel p,
//   mu_x = G * x, mu_y = G * y, m_xx = G * x^2, m_yy = G * y^2, m_xy = G * xy   (zero-padded, G symmetric),
//   s_x = m_xx - mu_x^2,  s_y = m_yy - mu_y^2,  s_xy = m_xy - mu_x mu_y,
//   S = A1 A2 / (B1 B2),  A1 = 2 mu_x mu_y + C1, A2 = 2 s_xy + C2, B1 = mu_x^2 + mu_y^2 + C1,
//   B2 = s_x + s_y + C2,
// the partials of S_p holding the other variances / means fixed are
//   dS/ds_x = -S / B2 =: b,   dS/ds_xy = 2 A1 / (B1 B2) =: c,   dS/dmu_x|_s = S (2 mu_y / A1 - 2 mu_x / B1).
// In the raw moments (mu_x, m_xx, m_xy), which are linear in x: dS/dm_xx = b, dS/dm_xy = c and
//   dS/dmu_x = dS/dmu_x|_s - 2 mu_x b - mu_y c =: a.
// Since dmu_x,p/dx_q = G(p - q), dm_xx,p/dx_q = 2 x_q G(p - q), dm_xy,p/dx_q = y_q G(p - q):
//   d(sum_p S_p)/dx_q = sum_p G(p - q) (a_p + 2 x_q b_p + y_q c_p) = (G * a)_q + 2 x_q (G * b)_q + y_q (G *
//   c)_q,
// i.e. the three partial maps blurred with the same zero-padded window (pixels p outside the image do not
// exist, so the sum runs over the image only: exactly the zero-padded blur).
double AddSsimChannel(const std::vector<double>& x, const std::vector<double>& y, int width, int height,
                      int channel, double scale, std::vector<double>* gradient) {
  const std::size_t pixels = x.size();
  const SsimMoments m = LocalSsimMoments(x, y, width, height);
  const std::vector<double>&mu_x = m.mu_x, &mu_y = m.mu_y;
  std::vector<double> a(pixels), b(pixels), c(pixels);
  double sum = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    const double A1 = 2 * mu_x[p] * mu_y[p] + kSsimC1, A2 = 2 * m.s_xy[p] + kSsimC2;
    const double B1 = mu_x[p] * mu_x[p] + mu_y[p] * mu_y[p] + kSsimC1, B2 = m.s_x[p] + m.s_y[p] + kSsimC2;
    const double S = A1 * A2 / (B1 * B2);
    sum += S;
    b[p] = -S / B2;
    c[p] = 2 * A1 / (B1 * B2);
    a[p] = S * (2 * mu_y[p] / A1 - 2 * mu_x[p] / B1) - 2 * mu_x[p] * b[p] - mu_y[p] * c[p];
  }
  const std::vector<double> blur_a = BlurWithSsimWindow(a, width, height);
  const std::vector<double> blur_b = BlurWithSsimWindow(b, width, height);
  const std::vector<double> blur_c = BlurWithSsimWindow(c, width, height);
  for (std::size_t q = 0; q < pixels; ++q)
    (*gradient)[3 * q + channel] += scale * (blur_a[q] + 2 * x[q] * blur_b[q] + y[q] * blur_c[q]);
  return sum;
}

}  // namespace

PhotometricLoss EvaluatePhotometricLoss(const RenderedView& rendered, const std::vector<float>& target_rgb,
                                        const std::vector<float>& target_depth,
                                        const PhotometricLossWeights& weights,
                                        const std::vector<std::uint8_t>& mask) {
  const int width = rendered.width, height = rendered.height;
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  assert(width > 0 && height > 0 && rendered.rgb.size() == 3 * pixels && target_rgb.size() == 3 * pixels);
  assert(target_depth.empty() || target_depth.size() == pixels);
  assert(mask.empty() || mask.size() == pixels);
  const double l = weights.ssim_weight, n = 3.0 * static_cast<double>(pixels);
  PhotometricLoss loss;
  auto masked = [&](std::size_t p) { return !mask.empty() && mask[p] == 0; };
  // The rendered rgb the loss sees: the target's at masked pixels.
  std::vector<float> r = rendered.rgb;
  for (std::size_t p = 0; p < pixels; ++p)
    if (masked(p))
      for (int c = 0; c < 3; ++c) r[3 * p + c] = target_rgb[3 * p + c];

  // L1 and its gradient (1 - l) sign(r - t) / n.
  std::vector<double> gradient(3 * pixels);
  double l1_sum = 0;
  for (std::size_t i = 0; i < 3 * pixels; ++i) {
    const double d = static_cast<double>(r[i]) - target_rgb[i];
    l1_sum += std::abs(d);
    gradient[i] = (1 - l) * Sign(d) / n;
  }
  loss.l1 = l1_sum / n;

  // D-SSIM = 1 - (sum S) / n: gradient -l / n d(sum S)/dx, per channel.
  double ssim_sum = 0;
  std::vector<double> x(pixels), y(pixels);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t p = 0; p < pixels; ++p) {
      x[p] = r[3 * p + c];
      y[p] = target_rgb[3 * p + c];
    }
    ssim_sum += AddSsimChannel(x, y, width, height, c, -l / n, &gradient);
  }
  for (std::size_t p = 0; p < pixels; ++p)  // r does not depend on the render where it is masked
    if (masked(p))
      for (int c = 0; c < 3; ++c) gradient[3 * p + c] = 0;
  loss.dssim = 1.0 - ssim_sum / n;
  loss.gradients.rgb.assign(gradient.begin(), gradient.end());
  loss.gradients.alpha.assign(pixels, 0.0f);
  loss.gradients.depth_sum.assign(pixels, 0.0f);

  // Depth: mean |E - d| / d over the valid pixels; dL/dE = w_d sign(E - d) / (d count), then through
  // E = D / alpha.
  if (!target_depth.empty()) {
    std::vector<float> dL_dE(pixels, 0.0f);
    double depth_sum = 0;
    std::size_t count = 0;
    auto valid = [&](std::size_t p) {
      return target_depth[p] > 0 && !masked(p) && rendered.alpha[p] >= 1e-4f &&
             std::isfinite(rendered.expected_depth[p]);
    };
    for (std::size_t p = 0; p < pixels; ++p)
      if (valid(p)) {
        depth_sum +=
            std::abs(static_cast<double>(rendered.expected_depth[p]) - target_depth[p]) / target_depth[p];
        ++count;
      }
    if (count > 0) {
      loss.depth = depth_sum / static_cast<double>(count);
      const float scale = static_cast<float>(weights.depth_weight / static_cast<double>(count));
      for (std::size_t p = 0; p < pixels; ++p)
        if (valid(p))
          dL_dE[p] = scale * static_cast<float>(Sign(rendered.expected_depth[p] - target_depth[p])) /
                     target_depth[p];
      AddExpectedDepthGradient(rendered, dL_dE, &loss.gradients);
    }
  }
  loss.total = (1 - l) * loss.l1 + l * loss.dssim + weights.depth_weight * loss.depth;
  return loss;
}

}  // namespace uf::splat
