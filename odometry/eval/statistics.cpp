#include "odometry/eval/statistics.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace uf {

ErrorStats ComputeStats(const std::vector<double>& errors) {
  assert(!errors.empty());
  ErrorStats s;
  s.n = errors.size();
  const double n = static_cast<double>(s.n);
  double sum = 0, sum_sq = 0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0;  // two-pass, as numpy does, rather than sum_sq/n - mean^2
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  auto [lo, hi] = std::minmax_element(errors.begin(), errors.end());
  s.min = *lo;
  s.max = *hi;
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = s.n / 2;
  s.median = s.n % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

}  // namespace uf
