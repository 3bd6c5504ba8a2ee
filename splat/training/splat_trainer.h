// SplatTrainer: optimizes a GaussianModel against training views on Vulkan compute (lavapipe without a
// GPU). An iteration is one command-buffer submission: forward render, photometric (+ depth) loss and its
// image gradient, backward through rasterization and projection, Adam update (vk/adam_pass.h). Between
// iterations the host densifies and prunes on the schedule of TrainingOptions (training/densify.h).
// Vulkan stays out of this header.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"
#include "splat/splat_renderer.h"
#include "splat/training/training_options.h"

namespace uf::splat {

struct IterationStats {
  int iteration = 0;                    // 1-based index of the step just taken
  double loss = 0;                      // total of the step's view
  double l1 = 0, dssim = 0, depth = 0;  // the terms before weighting
  std::size_t gaussians = 0;            // after the step (densification may change it)
  int active_sh_degree = 0;
  bool densified = false;  // the step ended with densification / pruning / opacity reset
  std::size_t cloned = 0, split = 0, pruned = 0;  // by that densification
  // Device time per stage of the step's submission (timestamp queries; empty when the queue has none):
  // the forward's stages, the loss's stages, "rasterize backward", "project backward", "adam".
  std::vector<std::pair<std::string, double>> stage_ms;
};

class SplatTrainer {
 public:
  // scene_extent: the radius of the training cameras around their centroid (m), >= 1e-3 (scales the position
  // learning rate and the densification sizes). The model is uploaded at options.sh_degree.
  static Expected<std::unique_ptr<SplatTrainer>> Create(const GaussianModel& initial,
                                                        const TrainingOptions& options, double scene_extent,
                                                        const SplatRendererOptions& device = {});
  ~SplatTrainer();
  SplatTrainer(const SplatTrainer&) = delete;
  SplatTrainer& operator=(const SplatTrainer&) = delete;

  // One optimization step on `view` (its image size must match its camera). `rendered_rgb` (optional)
  // receives the step's forward render (width x height x 3, before the update), e.g. for fitting the view's
  // exposure (training/exposure.h).
  Expected<IterationStats> Step(const TrainingView& view, std::vector<float>* rendered_rgb = nullptr);
  // The current model (downloaded from the device).
  Expected<GaussianModel> Model() const;
  // Renders the current model (evaluation, comparisons); does not change the optimizer state.
  Expected<RenderedView> Render(const SplatCamera& camera);

  int iteration() const;
  const std::string& device_name() const;

 private:
  struct Impl;
  explicit SplatTrainer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::splat
