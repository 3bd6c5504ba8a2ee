#include "odometry/eval/kitti_drift.h"

#include <cassert>
#include <cmath>
#include <numbers>

namespace uf {
namespace {

constexpr double kSegmentLengths[] = {100, 200, 300, 400, 500, 600, 700, 800};
constexpr std::size_t kStepFrames = 10;

// First frame after `first` whose path distance exceeds that of `first` by more than `length`.
std::ptrdiff_t LastFrameOfSegment(const std::vector<double>& distance, std::size_t first, double length) {
  for (std::size_t i = first; i < distance.size(); ++i)
    if (distance[i] > distance[first] + length) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

}  // namespace

KittiDrift ComputeKittiDrift(const std::vector<SE3>& reference, const std::vector<SE3>& estimate) {
  assert(reference.size() == estimate.size());
  std::vector<double> distance(reference.size(), 0.0);
  for (std::size_t i = 1; i < reference.size(); ++i)
    distance[i] = distance[i - 1] + (reference[i].translation() - reference[i - 1].translation()).norm();

  double sum_t = 0, sum_r = 0, reference_chords = 0, estimate_chords = 0;
  KittiDrift drift;
  for (std::size_t first = 0; first < reference.size(); first += kStepFrames) {
    for (double length : kSegmentLengths) {
      const std::ptrdiff_t last = LastFrameOfSegment(distance, first, length);
      if (last < 0) continue;
      const SE3 reference_delta = reference[first].inverse() * reference[last];
      const SE3 estimate_delta = estimate[first].inverse() * estimate[last];
      const SE3 error = estimate_delta.inverse() * reference_delta;
      sum_r += error.so3().angle() / length;  // acos of the clamped trace, as the devkit
      sum_t += error.translation().norm() / length;
      reference_chords += reference_delta.translation().norm();
      estimate_chords += estimate_delta.translation().norm();
      ++drift.segments;
    }
  }
  if (drift.segments == 0) return drift;
  const double n = static_cast<double>(drift.segments);
  drift.t_pct = 100.0 * sum_t / n;
  drift.r_deg_per_100m = 100.0 * (180.0 / std::numbers::pi) * sum_r / n;
  drift.scale_ppm = 1e6 * (estimate_chords / reference_chords - 1.0);
  return drift;
}

}  // namespace uf
