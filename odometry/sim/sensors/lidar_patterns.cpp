#include "odometry/sim/sensors/lidar_patterns.h"

#include <cmath>
#include <numbers>

namespace uf::sim {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// `count` elevations spread uniformly over [lowest, highest] degrees, ascending.
std::vector<double> Uniform(int count, double lowest_deg, double highest_deg) {
  std::vector<double> elevations(count);
  for (int i = 0; i < count; ++i) {
    elevations[i] = (lowest_deg + (highest_deg - lowest_deg) * i / (count - 1)) * kDegree;
  }
  return elevations;
}

// Rosette frequencies (Hz): oscillation through the centre and precession; the ratio is irrational (the
// golden ratio is the "most irrational" number, so the precession never locks onto the oscillation).
constexpr double kOscillationHz = 211.0;
constexpr double kPrecessionHz = kOscillationHz / (100.0 * std::numbers::phi);  // ~1.30 Hz

// frac(n * f * interval): the phase in cycles of a frequency f at point n, computed in long double so that
// stamps of a real epoch (n ~ 1e14) keep the phase exact to ~1e-6 cycles.
double Cycles(std::int64_t n, double frequency_hz) {
  const long double cycles_per_point =
      static_cast<long double>(frequency_hz) * static_cast<long double>(kLivoxPointIntervalNs) * 1e-9L;
  const long double cycles = static_cast<long double>(n) * cycles_per_point;
  return static_cast<double>(cycles - std::floor(cycles));
}

}  // namespace

std::optional<SpinningPattern> SpinningPatternFor(std::string_view model) {
  // Sources: Velodyne VLP-16 datasheet (16 beams, -15..+15 deg, 2 deg apart); Velodyne HDL-32E manual
  // (32 beams, -30.67..+10.67 deg, 1.33 deg apart); HDL-64E S2 datasheet (+2..-24.9 deg: an upper block of 32
  // beams about 1/3 deg apart down to -8.33 deg and a lower block of 32 about 1/2 deg apart from -8.83 deg;
  // HDL-64E-like, spacing uniform within each block, not the per-unit calibration); Ouster OS1-128 datasheet
  // (128 beams uniform over 45 deg, -22.5..+22.5, OS1-128-like).
  if (model == "spinning16") return SpinningPattern{Uniform(16, -15.0, 15.0)};
  if (model == "spinning32") return SpinningPattern{Uniform(32, -30.67, 10.67)};
  if (model == "spinning64") {
    std::vector<double> elevations = Uniform(32, -24.9, -8.83);
    const std::vector<double> upper = Uniform(32, -8.33, 2.0);
    elevations.insert(elevations.end(), upper.begin(), upper.end());
    return SpinningPattern{elevations};
  }
  if (model == "spinning128") return SpinningPattern{Uniform(128, -22.5, 22.5)};
  return std::nullopt;
}

bool IsKnownLidarModel(std::string_view model) {
  return model == "livox_avia" || SpinningPatternFor(model).has_value();
}

Eigen::Vector3d LivoxDirection(std::int64_t n) {
  const int head = static_cast<int>(((n % kLivoxHeads) + kLivoxHeads) % kLivoxHeads);
  const double oscillation = std::cos(2.0 * std::numbers::pi * Cycles(n, kOscillationHz));
  const double orientation =
      2.0 * std::numbers::pi * Cycles(n, kPrecessionHz) + head * std::numbers::pi / kLivoxHeads;
  // z = exp(i orientation) * oscillation, then scaled to the field of view.
  const double azimuth = std::cos(orientation) * oscillation * 0.5 * kLivoxHorizontalFovDeg * kDegree;
  const double elevation = std::sin(orientation) * oscillation * 0.5 * kLivoxVerticalFovDeg * kDegree;
  return Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
}

}  // namespace uf::sim
