// What splat training takes: the optimizer's schedule (3DGS defaults, Kerbl et al. 2023, with the
// densification schedule scaled to short CPU-friendly runs) and one training view.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "odometry/types/status.h"
#include "splat/render_types.h"

namespace uf::splat {

struct TrainingOptions {
  int iterations = 3000;  // optimizer steps (one training view each)
  int sh_degree = 3;      // final SH degree; the active degree starts at 0 and rises by one every
  int sh_degree_interval = 500;  // ... this many iterations (bands above it are held at zero)
  // Adam learning rates per parameter group. The position rate decays exponentially from initial to final
  // over the run and is multiplied by the scene extent (the radius of the camera centres, 3DGS' convention).
  double lr_position_initial = 1.6e-4, lr_position_final = 1.6e-6;
  double lr_log_scale = 5e-3, lr_rotation = 1e-3, lr_opacity = 0.05, lr_sh_dc = 2.5e-3, lr_sh_rest = 1.25e-4;
  double adam_beta1 = 0.9, adam_beta2 = 0.999, adam_epsilon = 1e-15;
  // Loss: (1 - ssim_weight) L1 + ssim_weight (1 - SSIM) on the rgb image, plus depth_weight times the mean
  // relative error |E - d| / d of the expected depth E on pixels with a LiDAR depth d (0: no depth loss;
  // splat/cpu_reference/photometric_loss.h).
  double ssim_weight = 0.2;
  double depth_weight = 0.0;
  // Densification every densify_interval iterations in [densify_from, densify_until): Gaussians whose mean
  // screen-space gradient (NDC units, averaged over the views that saw them) exceeds the threshold are cloned
  // (largest scale <= dense_fraction x extent) or split in two (larger); then those with opacity below
  // prune_opacity or larger than prune_world_fraction x extent are removed.
  int densify_from = 100, densify_until = 2000, densify_interval = 100;
  double densify_gradient_threshold = 2e-4;
  double dense_fraction = 0.01;
  double prune_opacity = 0.005;
  double prune_world_fraction = 0.1;
  // Opacities are clamped to 0.01 every this many iterations before densify_until, except in the run's last
  // half interval (they need the iterations after it to recover); 0: never.
  int opacity_reset_interval = 1000;
  std::size_t max_gaussians = 2'000'000;  // densification stops growing the model here
  RenderSettings render;                  // background etc. of the training renders
  std::uint64_t seed = 1;

  Status Validate() const;  // names the field and value, e.g. "iterations: must be > 0, got -3"
};

// One image to train on (or to evaluate against), at the training resolution.
struct TrainingView {
  SplatCamera camera;        // intrinsics at the training resolution, pose T_world_camera
  std::vector<float> rgb;    // width x height x 3, display-referred (sRGB) in [0, 1], row-major
  std::vector<float> depth;  // optional LiDAR depth t_z per pixel, m (0: none); empty: no depth
  // Optional, width x height: 0 where the image shows nothing to learn (not filled by an undistorted camera,
  // the car's own hood); masked pixels add nothing to the loss (cpu_reference/photometric_loss.h). Empty:
  // every pixel counts.
  std::vector<std::uint8_t> mask;
};

}  // namespace uf::splat
