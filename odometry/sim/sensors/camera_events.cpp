#include "odometry/sim/sensors/camera_events.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "odometry/sim/scene/lattice_noise.h"

namespace uf::sim {
namespace {

// (t - begin) / (end - begin) in the first of the windows holding t, or nullopt.
std::optional<double> ProgressInFirstWindow(const std::vector<TimeWindow>& windows, Stamp t) {
  for (const TimeWindow& window : windows)
    if (window.Contains(t))
      return static_cast<double>(t - window.begin) / static_cast<double>(window.end - window.begin);
  return std::nullopt;
}

}  // namespace

CameraConditions ConditionsAt(const CameraConfig& config, Stamp t) {
  CameraConditions conditions;
  conditions.noise_std_dn = config.noise_std_dn;
  for (const TimeWindow& window : config.darkness) {
    if (!window.Contains(t)) continue;
    conditions.illumination = kDarknessIllumination;
    conditions.noise_std_dn = config.noise_std_dn * kDarknessNoiseFactor;
    break;
  }
  double exposure_gain = config.exposure;
  for (const auto& [window, gain] : config.exposure_changes) {
    if (window.Contains(t)) exposure_gain *= gain;  // overlapping changes multiply
  }
  conditions.gain = exposure_gain * conditions.illumination;
  const std::optional<double> occluder = ProgressInFirstWindow(config.occlusions, t);
  conditions.occluded = occluder.has_value();
  conditions.occluder_progress = occluder.value_or(0.0);
  const std::optional<double> panel = ProgressInFirstWindow(config.passing_panels, t);
  conditions.passing = panel.has_value();
  conditions.passing_progress = panel.value_or(0.0);
  return conditions;
}

std::vector<float> OccluderTransmission(int width, int supersampling, double progress) {
  const double w = width;
  const double half_band = w / 6.0, blur = w / 30.0;
  const double centre = half_band + blur + progress * (w - 2.0 * half_band - 2.0 * blur);
  const int n = supersampling;
  std::vector<float> transmission(static_cast<std::size_t>(width));
  for (int u = 0; u < width; ++u) {
    double sum = 0.0;
    for (int sx = 0; sx < n; ++sx) {
      const double x = u + (sx + 0.5) / n;  // x' = x + 0.5 of the sub-sample
      const double d = std::abs(x - centre) - half_band;
      const double a = std::clamp((d + blur) / (2.0 * blur), 0.0, 1.0);
      sum += a * a * (3.0 - 2.0 * a);
    }
    transmission[static_cast<std::size_t>(u)] = static_cast<float>(sum / n);
  }
  return transmission;
}

PassingPanel PassingPanelAt(int width, int supersampling, double progress) {
  const double w = width;
  PassingPanel panel;
  panel.left_px = -0.5 * w + progress * 1.5 * w;
  const double right = panel.left_px + 0.5 * w;
  const int n = supersampling;
  panel.cover.resize(static_cast<std::size_t>(width));
  for (int u = 0; u < width; ++u) {
    int inside = 0;
    for (int sx = 0; sx < n; ++sx) {
      const double x = u + (sx + 0.5) / n;
      inside += x >= panel.left_px && x < right;
    }
    panel.cover[static_cast<std::size_t>(u)] = static_cast<float>(inside) / static_cast<float>(n);
  }
  return panel;
}

float PanelRadiance(const PassingPanel& panel, double x, double y) {
  constexpr std::uint32_t kSalt = 0x7A11E5u;
  return static_cast<float>(0.05 + 0.6 * noise::ValueNoise(x - panel.left_px, y, kPanelTextureCellPx, kSalt));
}

}  // namespace uf::sim
