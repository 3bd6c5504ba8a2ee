// The `splat:` section of a configuration file (`ultrafusion splat --config`, and `ultrafusion run --config`,
// which may carry it): every field of splat::TrainingOptions under its own name, plus what the command
// decides around the trainer (resolution, keyframe spacing, held-out stride, time budget). Every key is
// optional; unknown keys are an error naming the file, the key and its line. configs/splat.yaml lists every
// key with its default.
//
//   splat:
//     iterations: 3000              # optimizer steps, one training view each
//     time_budget_s: 0              # stop training after this many seconds (0: no limit)
//     resolution: [0, 0]            # training images W x H, px; [0, 0]: the camera's size halved until
//                                   #   the width is <= max_width
//     max_width: 320                # px, the default resolution's bound
//     keyframe_distance_m: 0.3      # an image is used when the camera moved this far since the last one
//     keyframe_angle_deg: 5         #   ... or turned this much
//     holdout_stride: 8             # every 8th selected image (index % 8 == 0) is held out for testing
//     comparisons: 4                # held-out views written to comparisons/
//     sh_degree: 3, sh_degree_interval: 500, lr_position_initial: 1.6e-4, ... (training_options.h)
//     background: [0, 0, 0]         # RenderSettings::background of the training renders
#pragma once

#include <filesystem>
#include <string>

#include "odometry/types/status.h"
#include "splat/training/training_options.h"

namespace uf::app {

struct SplatConfig {
  splat::TrainingOptions training;
  double time_budget_s = 0;   // 0: no limit
  int width = 0, height = 0;  // training resolution, px; 0 x 0: derived from the camera (see DefaultSize)
  int max_width = 320;
  double keyframe_distance_m = 0.3, keyframe_angle_deg = 5.0;
  int holdout_stride = 8;             // >= 2
  int comparisons = 4;                // >= 0
  std::size_t seed_points = 200'000;  // at most this many map points seed Gaussians (thinned evenly), > 0
  int sky_gaussians = 30'000;         // Gaussians on a sphere beyond the map for the sky (0: none)

  // Checks every field (the trainer's through TrainingOptions::Validate); the message names the field.
  Status Validate() const;
};

// Reads the `splat:` section of `file` onto `defaults` and validates the result; other known sections are
// skipped, unknown top-level keys are errors. A file without the section gives the defaults.
Expected<SplatConfig> LoadSplatConfig(const std::filesystem::path& file, SplatConfig defaults = {});

// "splat:\n  iterations: 3000\n..." with every key, readable by LoadSplatConfig.
std::string EmitSplatConfig(const SplatConfig& config);

// The default training size for a camera of width x height: halved (integer division keeps the aspect
// within a pixel) until the width is <= max_width.
void DefaultSize(int camera_width, int camera_height, int max_width, int& width, int& height);

}  // namespace uf::app
