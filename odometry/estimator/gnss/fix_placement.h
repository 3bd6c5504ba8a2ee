// Where a GNSS fix enters the window: between the two nodes around its stamp (GnssFactor at the fraction
// alpha = (t_fix - t_a) / (t_b - t_a)), or at one node (GnssFactorSinglePose).
//   - a fix at a node's stamp: that node alone;
//   - between nodes a < b at most config.max_interpolation_gap_s apart: a, b and alpha;
//   - otherwise (a longer gap, before the first or after the last node): the nearest node, if the fix is
//     within config.max_snap_s of it; else the fix has no place (wait for the next node, or drop it).
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "odometry/estimator/config/gnss_factor_config.h"
#include "odometry/types/stamp.h"

namespace uf::estimator {

struct FixPlacement {
  std::size_t node_a = 0, node_b = 0;  // indices into the node stamps; equal: one node
  double alpha = 0.0;                  // in [0, 1]; 0 for one node

  bool single_node() const { return node_a == node_b; }
};

// node_stamps strictly increasing (asserted in debug builds).
std::optional<FixPlacement> PlaceFix(Stamp fix_stamp, std::span<const Stamp> node_stamps,
                                     const GnssFactorConfig& config);

}  // namespace uf::estimator
