#include "odometry/sim/sensors/camera_events.h"

#include <algorithm>
#include <cmath>

namespace uf::sim {

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
  for (const TimeWindow& window : config.occlusions) {
    if (!window.Contains(t)) continue;
    conditions.occluded = true;
    conditions.occluder_progress =
        static_cast<double>(t - window.begin) / static_cast<double>(window.end - window.begin);
    break;
  }
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

}  // namespace uf::sim
