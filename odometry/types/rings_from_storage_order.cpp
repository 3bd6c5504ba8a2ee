#include "odometry/types/rings_from_storage_order.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace uf {
namespace {

constexpr double kTurn = 2 * std::numbers::pi;
constexpr double kMaxStepBack = 2.0 * std::numbers::pi / 180;  // the lasers' azimuth offsets, noise
constexpr double kShortOfWhole = 0.25;                         // the last ring may end early (no returns)
constexpr double kPastWhole = 0.05;

}  // namespace

int DeriveRingsFromStorageOrder(LidarScan& scan) {
  if (scan.has_ring || scan.points.size() < 2) return 0;
  // Azimuth unwrapped along the stored order, relative to the first point: each step taken in (-pi, pi].
  std::vector<double> turned(scan.points.size(), 0.0);
  double previous = std::atan2(scan.points[0].y, scan.points[0].x);
  for (std::size_t i = 1; i < scan.points.size(); ++i) {
    const double azimuth = std::atan2(scan.points[i].y, scan.points[i].x);
    const double step = std::remainder(azimuth - previous, kTurn);
    if (step < -kMaxStepBack) return 0;  // not stored ring by ring (or a gap of half a turn or more)
    turned[i] = turned[i - 1] + step;
    previous = azimuth;
  }
  const double turns = turned.back() / kTurn;
  const double rings = std::ceil(turns - kPastWhole);
  if (rings < kMinDerivedRings || rings > kMaxDerivedRings || turns < rings - kShortOfWhole) return 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    scan.points[i].ring =
        static_cast<std::uint16_t>(std::min(rings - 1, std::max(0.0, std::floor(turned[i] / kTurn))));
  scan.has_ring = true;
  return static_cast<int>(rings);
}

}  // namespace uf
