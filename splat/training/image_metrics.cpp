#include "splat/training/image_metrics.h"

#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>

namespace uf::splat {

const std::array<double, 2 * kSsimRadius + 1>& SsimWindow() {
  static const std::array<double, 2 * kSsimRadius + 1> window = [] {
    std::array<double, 2 * kSsimRadius + 1> g{};
    double sum = 0;
    for (int k = -kSsimRadius; k <= kSsimRadius; ++k) {
      g[k + kSsimRadius] = std::exp(-k * k / (2 * kSsimSigma * kSsimSigma));
      sum += g[k + kSsimRadius];
    }
    for (double& value : g) value /= sum;
    return g;
  }();
  return window;
}

std::vector<double> BlurWithSsimWindow(const std::vector<double>& image, int width, int height) {
  assert(width > 0 && height > 0 && image.size() == static_cast<std::size_t>(width) * height);
  const auto& g = SsimWindow();
  std::vector<double> rows(image.size(), 0.0), out(image.size(), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0;
      for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
        if (x + k >= 0 && x + k < width) sum += g[k + kSsimRadius] * image[y * width + x + k];
      rows[y * width + x] = sum;
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0;
      for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
        if (y + k >= 0 && y + k < height) sum += g[k + kSsimRadius] * rows[(y + k) * width + x];
      out[y * width + x] = sum;
    }
  return out;
}

double Psnr(const std::vector<float>& a, const std::vector<float>& b, std::span<const std::uint8_t> mask) {
  assert(a.size() == b.size() && !a.empty() && (mask.empty() || 3 * mask.size() == a.size()));
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!mask.empty() && mask[i / 3] == 0) continue;
    const double d = static_cast<double>(a[i]) - b[i];
    sum += d * d;
    ++count;
  }
  if (count == 0) return std::numeric_limits<double>::infinity();
  const double mse = sum / static_cast<double>(count);
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

SsimMoments LocalSsimMoments(const std::vector<double>& x, const std::vector<double>& y, int width,
                             int height) {
  const std::size_t pixels = x.size();
  std::vector<double> xx(pixels), yy(pixels), xy(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    xx[p] = x[p] * x[p];
    yy[p] = y[p] * y[p];
    xy[p] = x[p] * y[p];
  }
  SsimMoments m;
  m.mu_x = BlurWithSsimWindow(x, width, height);
  m.mu_y = BlurWithSsimWindow(y, width, height);
  m.s_x = BlurWithSsimWindow(xx, width, height);
  m.s_y = BlurWithSsimWindow(yy, width, height);
  m.s_xy = BlurWithSsimWindow(xy, width, height);
  for (std::size_t p = 0; p < pixels; ++p) {
    m.s_x[p] -= m.mu_x[p] * m.mu_x[p];
    m.s_y[p] -= m.mu_y[p] * m.mu_y[p];
    m.s_xy[p] -= m.mu_x[p] * m.mu_y[p];
  }
  return m;
}

double Ssim(const std::vector<float>& a, const std::vector<float>& b, int width, int height) {
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  assert(width > 0 && height > 0 && a.size() == 3 * pixels && b.size() == 3 * pixels);
  double total = 0;
  std::vector<double> x(pixels), y(pixels);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t p = 0; p < pixels; ++p) {
      x[p] = a[3 * p + c];
      y[p] = b[3 * p + c];
    }
    const SsimMoments m = LocalSsimMoments(x, y, width, height);
    for (std::size_t p = 0; p < pixels; ++p)
      total += ((2 * m.mu_x[p] * m.mu_y[p] + kSsimC1) * (2 * m.s_xy[p] + kSsimC2)) /
               ((m.mu_x[p] * m.mu_x[p] + m.mu_y[p] * m.mu_y[p] + kSsimC1) * (m.s_x[p] + m.s_y[p] + kSsimC2));
  }
  return total / (3.0 * static_cast<double>(pixels));
}

}  // namespace uf::splat
