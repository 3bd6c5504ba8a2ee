// The `splat:` section of a configuration file (`ultrafusion splat --config`, and `ultrafusion run --config`,
// which may carry it): every field of splat::TrainingOptions under its own name, plus what the command
// decides around the trainer (resolution, keyframe spacing, held-out stride, time budget). Its keys,
// defaults and units are in docs/CONFIG.md; the file is read by LoadConfigFile (config_file.h).
#pragma once

#include <string>

#include "odometry/types/status.h"
#include "splat/training/training_options.h"

namespace uf::app {

struct SplatConfig {
  splat::TrainingOptions training;
  double time_budget_s = 0;   // 0: no limit
  int width = 0, height = 0;  // training resolution, px; 0 x 0: derived from the camera (see DefaultSize)
  int max_width = 320;
  // Coarse to fine: a training size wider than max_width is first trained at the size halved until its width
  // is <= max_width (DefaultSize), doubled every coarse_to_fine_interval iterations (CoarseToFineSize).
  // 1000: on KITTI raw at 1242 x 375 (3000 iterations) as good as the full size throughout in 63 % of the
  // time.
  int coarse_to_fine_interval = 1000;  // iterations per size, >= 0; 0: the training size throughout
  double keyframe_distance_m = 0.3, keyframe_angle_deg = 5.0;
  int holdout_stride = 8;             // >= 2
  int comparisons = 4;                // >= 0
  std::size_t seed_points = 200'000;  // at most this many map points seed Gaussians (thinned evenly), > 0
  int feature_seed_corners = 600;     // corners per training image triangulated into seeds (0: none)
  int sky_gaussians = 30'000;         // Gaussians on a sphere beyond the map for the sky (0: none)
  std::string mask_image;  // PNG of the camera's size, black where the image shows nothing to learn; "": none
  // Exposure compensation (splat/training/exposure.h): each training image's gain and bias per channel are
  // fitted from exposure_from iterations on, towards (1, 0) with exposure_prior; held-out images take theirs
  // interpolated in time. Off by default: with a camera of fixed exposure (the simulator's) the fits absorb
  // the splats' own errors (-0.3 dB held out); on for automatic exposure (configs/kitti-raw.yaml).
  bool exposure_compensation = false;
  int exposure_from = 300;       // iterations, >= 0
  double exposure_prior = 0.01;  // >= 0

  // Checks every field (the trainer's through TrainingOptions::Validate); the message names the field.
  Status Validate() const;
};

// "splat:\n  iterations: 3000\n..." with every key.
std::string EmitSplatConfig(const SplatConfig& config);

// The default training size for a camera of width x height: halved (integer division keeps the aspect
// within a pixel) until the width is <= max_width.
void DefaultSize(int camera_width, int camera_height, int max_width, int& width, int& height);

// The size that iteration (0-based) trains at under coarse to fine (SplatConfig::coarse_to_fine_interval):
// width x height halved max(0, L - iteration / interval) times, L the halvings DefaultSize makes of it; with
// interval 0, or a size already <= max_width, width x height.
void CoarseToFineSize(const SplatConfig& config, int width, int height, int iteration, int& coarse_width,
                      int& coarse_height);

}  // namespace uf::app
