// Adaptive density control of splat training (3DGS, Kerbl et al. 2023, section 5.2) on the host state
// downloaded from the device (optimizer_state.h): Gaussians with a large mean screen-space gradient are
// cloned (small ones: under-reconstruction) or split (large ones: over-reconstruction); then transparent and
// huge ones are pruned. Also the periodic opacity reset. No Vulkan.
#pragma once

#include <cstddef>
#include <cstdint>

#include "splat/training/optimizer_state.h"
#include "splat/training/training_options.h"

namespace uf::splat {

struct DensifyResult {
  std::size_t cloned = 0, split = 0, pruned = 0;
};

// For each Gaussian with a view count > 0 and mean gradient accum / count >= densify_gradient_threshold:
//   clone  when its largest scale <= dense_fraction * scene_extent: an identical copy (moments zero);
//   split  otherwise: 2 children with means drawn from the parent's N(mu, Sigma) (Sigma = R S S^T R^T),
//          scales / 1.6 (log_scale - ln 1.6), the parent's rotation, opacity and SH, moments zero; the parent
//          is removed.
// Candidates are taken in index order; no more are added once the model would exceed options.max_gaussians.
// Then every Gaussian (new ones included) with opacity < prune_opacity or largest scale >
// prune_world_fraction * scene_extent is removed. Survivors keep their order and moments; new Gaussians
// follow them in their parents' order. The statistics are reset. Same seed -> same result.
DensifyResult DensifyAndPrune(OptimizerHostState& state, const TrainingOptions& options, double scene_extent,
                              std::uint64_t seed);

// Opacity reset (3DGS): logit = min(logit, logit(max_opacity)) with logit(a) = ln(a / (1 - a)); the Adam
// moments of every opacity are zeroed (3DGS replaces the optimizer's opacity tensor).
void ResetOpacity(OptimizerHostState& state, float max_opacity = 0.01f);

}  // namespace uf::splat
