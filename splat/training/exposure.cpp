#include "splat/training/exposure.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace uf::splat {
namespace {

// 8-bit values at the ends of the range: the sensor clipped them.
constexpr float kClipped = 0.5f / 255.0f;

struct ChannelFit {
  float gain = 1, bias = 0;
};

// The weighted normal equations of the header for channel c, with the weights of the previous fit (none
// for the first solve).
ChannelFit SolveChannel(std::span<const float> r, std::span<const float> t,
                        std::span<const std::uint8_t> mask, int c, const ChannelFit* previous,
                        const ExposureFitOptions& o) {
  double W = 0, S_r = 0, S_t = 0, S_rr = 0, S_rt = 0;
  for (std::size_t p = static_cast<std::size_t>(c); p < r.size(); p += 3) {
    if (!mask.empty() && mask[p / 3] == 0) continue;
    const double x = r[p], y = t[p];
    if (y < kClipped || y > 1.0f - kClipped || !std::isfinite(x)) continue;
    double w = 1;
    if (previous) {
      const double residual = std::abs(previous->gain * x + previous->bias - y);
      if (residual > o.huber_delta) w = o.huber_delta / residual;
    }
    W += w, S_r += w * x, S_t += w * y, S_rr += w * x * x, S_rt += w * x * y;
  }
  if (W <= 0) return {};
  const double prior = o.prior_weight * W;
  const double a = S_rr + prior, b = S_r, d = W + prior;
  const double det = a * d - b * b;  // > 0: the prior makes the matrix positive definite
  const double gain = (d * (S_rt + prior) - b * S_t) / det;
  const double bias = (a * S_t - b * (S_rt + prior)) / det;
  if (!std::isfinite(gain) || !std::isfinite(bias)) return {};
  return {std::clamp(static_cast<float>(gain), o.min_gain, o.max_gain),
          std::clamp(static_cast<float>(bias), -o.max_abs_bias, o.max_abs_bias)};
}

}  // namespace

Exposure FitExposure(std::span<const float> rendered, std::span<const float> image,
                     const ExposureFitOptions& options, std::span<const std::uint8_t> mask) {
  assert(rendered.size() == image.size() && rendered.size() % 3 == 0);
  assert(mask.empty() || 3 * mask.size() == image.size());
  Exposure exposure;
  for (int c = 0; c < 3; ++c) {
    ChannelFit fit = SolveChannel(rendered, image, mask, c, nullptr, options);
    for (int i = 0; i < options.reweightings; ++i)
      fit = SolveChannel(rendered, image, mask, c, &fit, options);
    exposure.gain[c] = fit.gain;
    exposure.bias[c] = fit.bias;
  }
  return exposure;
}

void ApplyExposure(const Exposure& exposure, std::span<float> rgb) {
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = exposure.gain[i % 3] * rgb[i] + exposure.bias[i % 3];
}

void RemoveExposure(const Exposure& exposure, std::span<float> rgb) {
  for (std::size_t i = 0; i < rgb.size(); ++i)
    rgb[i] = (rgb[i] - exposure.bias[i % 3]) / exposure.gain[i % 3];
}

Exposure InterpolateExposure(std::span<const Stamp> stamps, std::span<const Exposure> exposures,
                             Stamp stamp) {
  assert(stamps.size() == exposures.size());
  if (stamps.empty()) return {};
  const auto after = std::lower_bound(stamps.begin(), stamps.end(), stamp);
  if (after == stamps.begin()) return exposures.front();
  if (after == stamps.end()) return exposures.back();
  const std::size_t j = static_cast<std::size_t>(after - stamps.begin()), i = j - 1;
  const double s = static_cast<double>(stamp - stamps[i]) / static_cast<double>(stamps[j] - stamps[i]);
  Exposure e;
  for (int c = 0; c < 3; ++c) {
    e.gain[c] = static_cast<float>((1 - s) * exposures[i].gain[c] + s * exposures[j].gain[c]);
    e.bias[c] = static_cast<float>((1 - s) * exposures[i].bias[c] + s * exposures[j].bias[c]);
  }
  return e;
}

}  // namespace uf::splat
