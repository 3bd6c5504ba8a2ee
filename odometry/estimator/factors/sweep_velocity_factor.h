// Sweep-velocity prior of LiDAR-only odometry on scans kept apart (keyframes: each sweep has a begin and an
// end node of its own; docs/METHOD.md "Sweep-velocity prior"). The world-frame velocity within the sweep
// should be the velocity between the two previous scans' end nodes a and b:
//
//   r = [ (t_end - t_begin) / dt_sweep - (t_b - t_a) / dt_ref ] / sigma,   sigma = acc_density sqrt(dt_mid)
//
// (translations of T_world_body; dt_mid the time between the middles of the two intervals, white-noise
// acceleration as in constant_velocity_factor.h). Only translations enter: the rotation within a sweep is
// well observed by its points, while its translation is not where the scene pins translation weakly (a
// shear of the sweep along the ground), and the world-frame velocity of a carried or driven sensor changes
// slowly where its body frame turns fast. Unlike the three-node constant-velocity prior, it does not tie the
// new scan's position to an extrapolation: only the shape of the sweep.
// Jacobians by Ceres automatic differentiation in the ambient {t, q} blocks.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

namespace uf::estimator {

struct SweepVelocityTiming {
  double dt_reference = 0;  // s, from node a to node b
  double dt_sweep = 0;      // s, from the begin to the end node
  double dt_mid = 0;        // s, between the middles of the two intervals
};

// Durations > 0 and acc_density > 0 (asserted). Blocks: pose_a, pose_b, pose_begin, pose_end (7 each).
std::unique_ptr<ceres::CostFunction> MakeSweepVelocityFactor(const SweepVelocityTiming& timing,
                                                             double acc_density);

}  // namespace uf::estimator
