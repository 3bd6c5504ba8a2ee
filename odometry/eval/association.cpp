#include "odometry/eval/association.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace uf {
namespace {

std::vector<double> Float64Seconds(const std::vector<Stamp>& stamps, double offset) {
  std::vector<double> seconds;
  seconds.reserve(stamps.size());
  for (Stamp t : stamps) seconds.push_back(ToSeconds(t) + offset);
  return seconds;
}

// Index of the value in `sorted` nearest to `t` (the first on a tie, as numpy's argmin).
std::size_t Nearest(const std::vector<double>& sorted, double t) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), t);
  if (it == sorted.begin()) return 0;
  if (it == sorted.end()) return sorted.size() - 1;
  const std::size_t after = static_cast<std::size_t>(it - sorted.begin());
  return std::abs(sorted[after - 1] - t) <= std::abs(sorted[after] - t) ? after - 1 : after;
}

}  // namespace

Association AssociateByStamp(const std::vector<Stamp>& reference, const std::vector<Stamp>& estimate,
                             Stamp max_dt, Stamp estimate_offset) {
  Association association;
  if (reference.empty() || estimate.empty()) return association;
  const bool estimate_longer = estimate.size() > reference.size();
  const double offset = ToSeconds(estimate_offset);
  const std::vector<double> shorter = Float64Seconds(estimate_longer ? reference : estimate, 0.0);
  const std::vector<double> longer =
      Float64Seconds(estimate_longer ? estimate : reference, estimate_longer ? offset : -offset);
  std::vector<std::size_t>& short_index = estimate_longer ? association.reference : association.estimate;
  std::vector<std::size_t>& long_index = estimate_longer ? association.estimate : association.reference;
  const double max_difference = ToSeconds(max_dt);
  for (std::size_t i = 0; i < shorter.size(); ++i) {
    const std::size_t j = Nearest(longer, shorter[i]);
    if (!(std::abs(longer[j] - shorter[i]) <= max_difference)) continue;
    short_index.push_back(i);
    long_index.push_back(j);
  }
  return association;
}

Expected<Association> AssociateByIndex(std::size_t reference_size, std::size_t estimate_size) {
  if (reference_size != estimate_size)
    return Status::Error("without stamps poses are paired by index, but the reference has " +
                         std::to_string(reference_size) + " poses and the estimate " +
                         std::to_string(estimate_size) + " (give --ref-times/--est-times to pair by time)");
  Association association;
  for (std::size_t i = 0; i < reference_size; ++i) {
    association.reference.push_back(i);
    association.estimate.push_back(i);
  }
  return association;
}

}  // namespace uf
