#include "odometry/types/azimuth_convention.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace uf {
namespace {

constexpr double kPi = std::numbers::pi;

constexpr std::array<AzimuthConvention, 7> kAll = {
    AzimuthConvention{AzimuthSweep::kClockwise, SweepStart::kBehind},
    AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kBehind},
    AzimuthConvention{AzimuthSweep::kClockwise, SweepStart::kAhead},
    AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kAhead},
    AzimuthConvention{AzimuthSweep::kClockwise, SweepStart::kFirstPoint},
    AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kFirstPoint},
    kNoDeskew,
};

std::string_view StartKey(SweepStart start) {
  switch (start) {
    case SweepStart::kBehind:
      return "behind";
    case SweepStart::kAhead:
      return "ahead";
    case SweepStart::kFirstPoint:
      return "first_point";
  }
  return "behind";
}

double Azimuth(const LidarPoint& point) {
  return std::atan2(static_cast<double>(point.y), static_cast<double>(point.x));
}

// The swept angle w in [0, 2 pi] of a point at azimuth a (see the header), before the seam of the first
// point is resolved.
double Swept(double a, double start_azimuth, const AzimuthConvention& convention) {
  const bool clockwise = convention.sweep == AzimuthSweep::kClockwise;
  if (convention.start == SweepStart::kBehind) return clockwise ? kPi - a : kPi + a;  // one turn already
  double w = clockwise ? start_azimuth - a : a - start_azimuth;
  if (w < 0) w += 2 * kPi;
  if (w >= 2 * kPi) w -= 2 * kPi;
  return w;
}

}  // namespace

std::string AzimuthConventionKey(const AzimuthConvention& convention) {
  if (convention.sweep == AzimuthSweep::kNone) return "none";
  return std::string(convention.sweep == AzimuthSweep::kClockwise ? "clockwise" : "counter_clockwise") +
         "_from_" + std::string(StartKey(convention.start));
}

std::optional<AzimuthConvention> ParseAzimuthConvention(std::string_view key) {
  for (const AzimuthConvention& convention : kAll)
    if (AzimuthConventionKey(convention) == key) return convention;
  return std::nullopt;
}

std::string AzimuthConventionText(const AzimuthConvention& convention) {
  if (convention.sweep == AzimuthSweep::kNone) return "none (no deskew)";
  const char* start = convention.start == SweepStart::kBehind  ? "behind"
                      : convention.start == SweepStart::kAhead ? "ahead"
                                                               : "the first point";
  return std::string(convention.sweep == AzimuthSweep::kClockwise ? "clockwise" : "counter-clockwise") +
         " from " + start;
}

AzimuthConvention Reversed(const AzimuthConvention& convention) {
  AzimuthConvention reversed = convention;
  if (convention.sweep == AzimuthSweep::kClockwise) reversed.sweep = AzimuthSweep::kCounterClockwise;
  if (convention.sweep == AzimuthSweep::kCounterClockwise) reversed.sweep = AzimuthSweep::kClockwise;
  return reversed;
}

void DeriveAzimuthPointTimes(LidarScan& scan, Stamp sweep_period, const AzimuthConvention& convention) {
  scan.end = scan.stamp + sweep_period;
  scan.has_point_times = true;
  scan.point_times_from_azimuth = true;
  const double period = static_cast<double>(sweep_period);
  if (convention.sweep == AzimuthSweep::kNone) {
    for (LidarPoint& point : scan.points) point.offset_ns = static_cast<std::int32_t>(sweep_period / 2);
    return;
  }
  if (scan.points.empty()) return;
  const bool first_point = convention.start == SweepStart::kFirstPoint;
  const double start_azimuth = convention.start == SweepStart::kAhead ? 0.0
                               : first_point                          ? Azimuth(scan.points.front())
                                                                      : kPi;
  const double ns_per_radian = period / (2 * kPi);
  for (LidarPoint& point : scan.points) {
    double w = Swept(Azimuth(point), start_azimuth, convention);
    if (first_point) {
      const bool hint_at_start = point.offset_ns < sweep_period / 2;
      if (hint_at_start && w > 1.5 * kPi) w = 0;         // fired just before the first point
      if (!hint_at_start && w < 0.5 * kPi) w = 2 * kPi;  // a whole turn after it
    }
    point.offset_ns = static_cast<std::int32_t>(
        std::clamp(std::llround(w * ns_per_radian), 0LL, static_cast<long long>(sweep_period)));
  }
}

}  // namespace uf
