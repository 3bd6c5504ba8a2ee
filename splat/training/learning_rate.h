// The position learning-rate schedule of splat training (3DGS' get_expon_lr_func without the delay): a
// log-linear interpolation from lr_position_initial at step 0 to lr_position_final at options.iterations,
//   lr(step) = exp((1 - t) ln(lr_initial) + t ln(lr_final)) * scene_extent,  t = clamp(step / iterations, 0,
//   1),
// multiplied by the scene extent so that position steps scale with the scene (3DGS' spatial_lr_scale).
#pragma once

#include "splat/training/training_options.h"

namespace uf::splat {

// options valid (both rates > 0, iterations > 0); steps outside [0, iterations] are clamped.
double PositionLearningRate(const TrainingOptions& options, int step, double scene_extent);

}  // namespace uf::splat
