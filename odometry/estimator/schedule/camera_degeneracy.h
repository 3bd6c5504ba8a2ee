// The camera's degeneracy score of the reliability scheduling (docs/METHOD.md "Factor-wise reliability
// scheduling"; paper Sec. III-D, the visual reliability check), per frame of the visual front end:
//   D = w_f (1 - min(1, N_f / N_ref)) + w_g (1 - G_f) + w_r min(1, e / tau_r)
// N_f: the tracks carried into the frame (new corners constrain nothing yet), G_f: the share of the 8x8
// grid cells holding a feature, e: the mean epipolar (Sampson) error of the inliers, px: the front end's
// stand-in for the paper's mean reprojection residual, which needs the visual factor in a window. Fewer
// than min_tracks tracks (the paper's N_min) is degenerate: D = 1.
#pragma once

namespace uf::estimator {

struct CameraScoreConfig {
  double reference_tracks = 75;      // N_ref: half the front end's 150 features
  int min_tracks = 20;               // N_min
  double residual_threshold_px = 1;  // tau_r: the front end's RANSAC threshold
  double weight_tracks = 0.5, weight_grid = 0.25, weight_residual = 0.25;  // w_f, w_g, w_r (sum 1)
};

struct CameraDegeneracy {
  int tracks = 0;
  double grid_occupancy = 0;
  double epipolar_error_px = 0;
  double score = 1.0;  // D in [0, 1]
};

CameraDegeneracy ScoreCameraFrame(int tracks, double grid_occupancy, double epipolar_error_px,
                                  const CameraScoreConfig& config = {});

}  // namespace uf::estimator
