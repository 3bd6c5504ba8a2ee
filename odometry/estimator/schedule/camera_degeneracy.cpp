#include "odometry/estimator/schedule/camera_degeneracy.h"

#include <algorithm>

namespace uf::estimator {

CameraDegeneracy ScoreCameraFrame(int tracks, double grid_occupancy, double epipolar_error_px,
                                  const CameraScoreConfig& c) {
  CameraDegeneracy d{tracks, grid_occupancy, epipolar_error_px, 1.0};
  if (tracks < c.min_tracks) return d;
  const double few_tracks = 1.0 - std::min(1.0, tracks / c.reference_tracks);
  const double uneven = 1.0 - std::clamp(grid_occupancy, 0.0, 1.0);
  const double residual = std::min(1.0, std::max(0.0, epipolar_error_px) / c.residual_threshold_px);
  d.score = std::clamp(c.weight_tracks * few_tracks + c.weight_grid * uneven + c.weight_residual * residual,
                       0.0, 1.0);
  return d;
}

}  // namespace uf::estimator
