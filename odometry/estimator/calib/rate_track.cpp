#include "odometry/estimator/calib/rate_track.h"

#include <algorithm>

namespace uf::estimator {

std::vector<RateSample> IntervalRates(std::span<const double> t, std::span<const SO3> R_world_sensor) {
  std::vector<RateSample> rates;
  const std::size_t n = std::min(t.size(), R_world_sensor.size());
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double dt = t[i + 1] - t[i];
    if (!(dt > 0)) continue;
    const Eigen::Vector3d phi = (R_world_sensor[i].inverse() * R_world_sensor[i + 1]).Log();
    rates.push_back({0.5 * (t[i] + t[i + 1]), phi / dt});
  }
  return rates;
}

std::vector<RateSample> BoxSmoothed(std::span<const RateSample> track, double width) {
  std::vector<RateSample> out(track.begin(), track.end());
  if (!(width > 0)) return out;
  // Running sums over a window [lo, hi) that slides with the sample.
  std::size_t lo = 0, hi = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < track.size(); ++i) {
    const double t = track[i].t;
    while (hi < track.size() && track[hi].t <= t + 0.5 * width) sum += track[hi++].omega;
    while (lo < hi && track[lo].t < t - 0.5 * width) sum -= track[lo++].omega;
    out[i].omega = sum / static_cast<double>(hi - lo);
  }
  return out;
}

std::optional<Eigen::Vector3d> InterpolateRate(std::span<const RateSample> track, double t) {
  if (track.empty() || t < track.front().t || t > track.back().t) return std::nullopt;
  if (track.size() == 1) return track.front().omega;
  const auto after = std::upper_bound(track.begin(), track.end(), t,
                                      [](double value, const RateSample& s) { return value < s.t; });
  const std::size_t j =
      std::min<std::size_t>(std::max<std::ptrdiff_t>(after - track.begin(), 1), track.size() - 1);
  const std::size_t i = j - 1;
  const double h = track[j].t - track[i].t;
  const double s = (t - track[i].t) / h;
  const Eigen::Vector3d& p0 = track[i].omega;
  const Eigen::Vector3d& p1 = track[j].omega;
  if (i == 0 || j + 1 == track.size()) return ((1 - s) * p0 + s * p1).eval();
  // Catmull-Rom tangents (per unit of s) from the neighbours, scaled to this interval's length.
  const Eigen::Vector3d m0 = (p1 - track[i - 1].omega) / (track[j].t - track[i - 1].t) * h;
  const Eigen::Vector3d m1 = (track[j + 1].omega - p0) / (track[j + 1].t - track[i].t) * h;
  const double s2 = s * s, s3 = s2 * s;
  return ((2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1)
      .eval();
}

double MedianSpacing(std::span<const RateSample> track) {
  if (track.size() < 2) return 0.0;
  std::vector<double> gaps;
  for (std::size_t i = 0; i + 1 < track.size(); ++i) gaps.push_back(track[i + 1].t - track[i].t);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2];
}

}  // namespace uf::estimator
