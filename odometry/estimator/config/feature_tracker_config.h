// Options of the visual front end (visual/feature_tracker.h; docs/METHOD.md "Visual front end"), with the
// paper's defaults. In the config library so that configuration parsing does not link OpenCV.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct FeatureTrackerConfig {
  int max_features = 150;            // corners kept per frame (the paper's 150)
  double min_distance_px = 30;       // between features (the paper's 30 px)
  double quality_level = 0.01;       // Shi-Tomasi: relative to the frame's strongest corner response
  int klt_window_px = 15;            // side of the Lucas-Kanade window, odd
  int klt_pyramid_levels = 3;        // levels above the full resolution
  double max_fb_error_px = 0.5;      // forward-backward: the track tracked back must land this close
  double ransac_threshold_px = 1.0;  // epipolar distance of a RANSAC inlier, undistorted pixels
  double ransac_confidence = 0.99;
  int min_track_length = 4;          // frames a track needs before the estimator may use it
  double keyframe_parallax_px = 10;  // mean undistorted parallax against the last keyframe
  int grid_cells = 8;                // occupancy grid: grid_cells x grid_cells cells
  double min_contrast_dn = 3.0;      // intensity standard deviation below which a frame is textureless
  // Map every frame to the same mean and spread before tracking (a global gain and offset), so that tracks
  // survive exposure and illumination changes; the statistics stay those of the frame as recorded.
  bool normalize_exposure = true;
  // Gaussian smoothing of every frame before corners and Lucas-Kanade, pixels (0: none). For a camera that
  // aliases, one that samples the scene at points (the simulator's, one ray per pixel: configs/run-sim.yaml
  // sets 0.8): its aliases move against the scene, and smoothing damps them more than the coarser texture
  // the tracks should follow (docs/METHOD.md "Visual front end", step 0). Off for a camera whose optics
  // blur within a pixel, as real ones mostly do. At most kMaxSmoothingSigmaPx: wider blurs away the corners
  // themselves.
  double smoothing_sigma_px = 0;
  static constexpr double kMaxSmoothingSigmaPx = 5;
};

// The first bad field, e.g. "max_features: must be at least 1, got 0"; ok otherwise.
Status ValidateFeatureTrackerConfig(const FeatureTrackerConfig& config);

}  // namespace uf::estimator
