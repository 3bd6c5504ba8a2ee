#include "odometry/estimator/calib/time_offset_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

// Pearson correlation of x and y (0 when either is constant).
double Correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
  mx /= n, my /= n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxy += (x[k] - mx) * (y[k] - my);
    sxx += (x[k] - mx) * (x[k] - mx);
    syy += (y[k] - my) * (y[k] - my);
  }
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

double Huber(double r, double k) { return r <= k ? 0.5 * r * r : k * (r - 0.5 * k); }

// The vertex offset of the parabola through (-1, a), (0, b), (1, c), in steps, clamped to [-1, 1].
double ParabolaVertex(double a, double b, double c) {
  const double curvature = a - 2 * b + c;
  if (curvature == 0) return 0.0;
  return std::clamp(0.5 * (a - c) / curvature, -1.0, 1.0);
}

// The minimum of cost(centre + i step) over i in [-n, n], refined by a parabola through it and its
// neighbours (not at the ends of the grid).
template <typename Cost>
double ArgminOnGrid(double centre, double step, int n, const Cost& cost) {
  std::vector<double> values(2 * n + 1);
  for (int i = -n; i <= n; ++i) values[i + n] = cost(centre + i * step);
  const int best = static_cast<int>(std::min_element(values.begin(), values.end()) - values.begin());
  double argmin = centre + (best - n) * step;
  if (best > 0 && best < 2 * n)
    argmin += step * ParabolaVertex(values[best - 1], values[best], values[best + 1]);
  return argmin;
}

struct Matching {
  std::span<const RateSample> imu;  // box-filtered, only the samples every shift can match
  std::span<const RateSample> lidar;
};

double NormCorrelation(const Matching& m, double shift) {
  std::vector<double> x, y;
  x.reserve(m.imu.size()), y.reserve(m.imu.size());
  for (const RateSample& s : m.imu) {
    const std::optional<Eigen::Vector3d> w = InterpolateRate(m.lidar, s.t + shift);
    if (!w) continue;
    x.push_back(s.omega.norm());
    y.push_back(w->norm());
  }
  return x.size() >= 3 ? Correlation(x, y) : 0.0;
}

// J(shift) with R and b fitted at the shift; `fit` receives them.
double RobustCost(const Matching& m, double shift, double huber, RotationFit* fit) {
  std::vector<RatePair> pairs;
  pairs.reserve(m.imu.size());
  for (const RateSample& s : m.imu)
    if (const std::optional<Eigen::Vector3d> w = InterpolateRate(m.lidar, s.t + shift))
      pairs.push_back({*w, s.omega});
  if (pairs.size() < 3) return std::numeric_limits<double>::infinity();
  const RotationFit f = FitRotationRobust(pairs, huber);
  double cost = 0;
  for (const RatePair& p : pairs)
    cost += Huber((f.R_imu_lidar * p.lidar + f.gyro_bias - p.imu).norm(), huber);
  if (fit) *fit = f;
  return cost / static_cast<double>(pairs.size());
}

}  // namespace

TimeOffsetEstimate SearchTimeOffset(std::span<const RateSample> gyro, std::span<const RateSample> lidar,
                                    const TimeOffsetSearchOptions& o) {
  TimeOffsetEstimate e;
  if (lidar.size() < 4 || gyro.size() < 4) {
    e.rejected = "too few samples";
    return e;
  }
  const std::vector<RateSample> smoothed = BoxSmoothed(gyro, MedianSpacing(lidar));
  // The IMU samples that every shift in the range can match.
  const double from = lidar.front().t + o.max_shift_s, to = lidar.back().t - o.max_shift_s;
  std::size_t first = 0, last = 0;
  while (first < smoothed.size() && smoothed[first].t < from) ++first;
  last = first;
  while (last < smoothed.size() && smoothed[last].t <= to) ++last;
  const Matching m{std::span(smoothed).subspan(first, last - first), lidar};
  e.overlap_s = m.imu.size() >= 2 ? m.imu.back().t - m.imu.front().t : 0.0;
  if (e.overlap_s < o.min_overlap_s) {
    e.rejected = PrintfText("overlap %.1f s < %.1f s", e.overlap_s, o.min_overlap_s);
    return e;
  }
  double mean = 0, square = 0;
  for (const RateSample& s : m.imu) mean += s.omega.norm(), square += s.omega.squaredNorm();
  mean /= static_cast<double>(m.imu.size());
  e.rate_std_rad_s = std::sqrt(std::max(0.0, square / static_cast<double>(m.imu.size()) - mean * mean));

  // Coarse: the robust cost's minimum on the grid, on every k-th IMU sample (about 4 per LiDAR interval),
  // then a parabola through it. The rate norms' correlation peak, the paper's coarse step, moves by tens of
  // ms when a few LiDAR poses are wrong (a failed registration puts a spike into two interval rates); the
  // Huber cost does not.
  const std::size_t stride = std::max<std::size_t>(
      1, static_cast<std::size_t>(MedianSpacing(lidar) / 4.0 / std::max(MedianSpacing(m.imu), 1e-9)));
  std::vector<RateSample> sparse;
  for (std::size_t k = 0; k < m.imu.size(); k += stride) sparse.push_back(m.imu[k]);
  const Matching coarse_matching{sparse, lidar};
  const int steps = static_cast<int>(std::floor(o.max_shift_s / o.coarse_step_s));
  const double coarse = ArgminOnGrid(0.0, o.coarse_step_s, steps, [&](double shift) {
    return RobustCost(coarse_matching, shift, o.huber_rad_s, nullptr);
  });

  // Fine: the robust cost's minimum around the coarse shift, then a parabola through it.
  const int fine = static_cast<int>(std::ceil(2 * o.coarse_step_s / o.fine_step_s));
  e.shift_s = ArgminOnGrid(coarse, o.fine_step_s, fine,
                           [&](double shift) { return RobustCost(m, shift, o.huber_rad_s, nullptr); });
  e.cost = RobustCost(m, e.shift_s, o.huber_rad_s, &e.fit);
  e.correlation = NormCorrelation(m, e.shift_s);
  e.cost_at_zero = RobustCost(m, 0.0, o.huber_rad_s, nullptr);

  if (!std::isfinite(e.shift_s) || !std::isfinite(e.cost) || !std::isfinite(e.correlation))
    e.rejected = "not finite";
  else if (e.rate_std_rad_s < o.min_rate_std_rad_s)
    e.rejected = PrintfText("too little rotation: |w_I| varies by %.3f rad/s < %.3f", e.rate_std_rad_s,
                            o.min_rate_std_rad_s);
  else if (e.correlation < o.min_correlation)
    e.rejected = PrintfText("correlation %.2f < %.2f", e.correlation, o.min_correlation);
  else if (std::abs(e.shift_s) > o.max_shift_s - o.coarse_step_s)
    e.rejected = PrintfText("shift %.3f s at the end of the search range +-%.3f s", e.shift_s, o.max_shift_s);
  else if (e.cost > e.cost_at_zero)
    e.rejected = PrintfText("cost %.3g above the zero shift's %.3g", e.cost, e.cost_at_zero);
  return e;
}

}  // namespace uf::estimator
