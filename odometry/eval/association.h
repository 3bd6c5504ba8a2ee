// Pairs poses of a reference and an estimate, as evo's sync.associate_trajectories does: for each stamp of
// the trajectory with fewer poses (the estimate when both have as many), the nearest stamp of the other (the
// first on ties, so a pose of the longer one may be used twice), kept when |dt| <= max_dt.
// Distances are compared in float64 seconds exactly as evo computes them (offset added to the longer
// trajectory's stamps, or subtracted from them when the estimate is the shorter): a decimal tie between two
// neighbours (it happens in TUM fr2/desk) is then broken by the same rounding as in evo.
#pragma once

#include <cstddef>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

struct Association {
  std::vector<std::size_t> reference, estimate;  // matched indices, pair k = (reference[k], estimate[k])
  std::size_t size() const { return reference.size(); }
};

// `estimate_offset` is added to the estimate's stamps before matching (evo's --t_offset).
Association AssociateByStamp(const std::vector<Stamp>& reference, const std::vector<Stamp>& estimate,
                             Stamp max_dt, Stamp estimate_offset = 0);

// Pose i with pose i; both trajectories must have the same number of poses (as evo's kitti mode requires).
Expected<Association> AssociateByIndex(std::size_t reference_size, std::size_t estimate_size);

}  // namespace uf
