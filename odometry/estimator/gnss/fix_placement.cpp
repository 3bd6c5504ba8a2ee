#include "odometry/estimator/gnss/fix_placement.h"

#include <algorithm>
#include <cassert>
#include <cstdlib>

namespace uf::estimator {
namespace {

double Seconds(Stamp from, Stamp to) { return ToSeconds(to - from); }

std::optional<FixPlacement> Snap(Stamp fix_stamp, std::span<const Stamp> nodes, std::size_t node,
                                 const GnssFactorConfig& config) {
  if (std::abs(Seconds(nodes[node], fix_stamp)) > config.max_snap_s) return std::nullopt;
  return FixPlacement{node, node, 0.0};
}

}  // namespace

std::optional<FixPlacement> PlaceFix(Stamp fix_stamp, std::span<const Stamp> node_stamps,
                                     const GnssFactorConfig& config) {
  assert(std::adjacent_find(node_stamps.begin(), node_stamps.end(), std::greater_equal<Stamp>()) ==
         node_stamps.end());
  if (node_stamps.empty()) return std::nullopt;
  const auto after = std::lower_bound(node_stamps.begin(), node_stamps.end(), fix_stamp);
  const std::size_t b = static_cast<std::size_t>(after - node_stamps.begin());
  if (b == node_stamps.size()) return Snap(fix_stamp, node_stamps, b - 1, config);  // after the last node
  if (node_stamps[b] == fix_stamp) return FixPlacement{b, b, 0.0};
  if (b == 0) return Snap(fix_stamp, node_stamps, 0, config);  // before the first node
  const std::size_t a = b - 1;
  const double gap = Seconds(node_stamps[a], node_stamps[b]);
  if (gap <= config.max_interpolation_gap_s)
    return FixPlacement{a, b, Seconds(node_stamps[a], fix_stamp) / gap};
  const bool nearer_a = fix_stamp - node_stamps[a] <= node_stamps[b] - fix_stamp;
  return Snap(fix_stamp, node_stamps, nearer_a ? a : b, config);
}

}  // namespace uf::estimator
