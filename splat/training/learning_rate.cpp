#include "splat/training/learning_rate.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace uf::splat {

double PositionLearningRate(const TrainingOptions& options, int step, double scene_extent) {
  assert(options.iterations > 0 && options.lr_position_initial > 0 && options.lr_position_final > 0);
  const double t = std::clamp(static_cast<double>(step) / options.iterations, 0.0, 1.0);
  const double log_lr =
      (1.0 - t) * std::log(options.lr_position_initial) + t * std::log(options.lr_position_final);
  return std::exp(log_lr) * scene_extent;
}

}  // namespace uf::splat
