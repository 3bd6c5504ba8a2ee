// The training loop of `ultrafusion splat` and of run's splat stage: splat::SplatTrainer over the training
// views in a seeded shuffled order (a new permutation each pass, std::mt19937_64 on TrainingOptions::seed),
// one view per iteration, until the iteration count or the time budget is reached; then the held-out and
// (a sample of) the training views are rendered and scored with PSNR and SSIM (splat/training/
// image_metrics.h, the 3DGS conventions). With exposure compensation (splat/training/exposure.h) each
// training view is trained against its image brought to the canonical exposure, its exposure refitted from
// the render of each of its steps from SplatConfig::exposure_from on; views are scored with the render in
// their exposure (the training views' own, the held-out views' interpolated in time). Under coarse to fine
// (SplatConfig::coarse_to_fine_interval) the first steps train on the views resized (splat::ResizeView);
// the scores are at the training size.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "splat/training/exposure.h"
#include "splat/training/splat_trainer.h"
#include "viewer/app/config/splat_config.h"
#include "viewer/pipeline/splat/splat_views.h"

namespace uf::pipeline {

using app::SplatConfig;

struct TrainingProgress {
  int iteration = 0, iterations = 0;  // done, planned
  double loss = 0;                    // of the last step
  std::size_t gaussians = 0;
  int width = 0, height = 0;  // the size the step trained at (coarse to fine: smaller at first)
};

struct ViewScore {
  Stamp stamp = 0;
  double psnr = 0, ssim = 0;
};

struct SplatScores {
  double psnr = 0, ssim = 0;     // means over the views
  std::vector<ViewScore> views;  // per view, in the order given
};

// The steps trained at one size: all of them at the training size, or one entry per size of coarse to fine.
struct TrainingSize {
  int width = 0, height = 0;
  int iterations = 0;
  double seconds = 0;
};

struct SplatTrainingResult {
  std::unique_ptr<splat::SplatTrainer> trainer;  // holds the trained model (Model(), Render())
  int iterations = 0;
  double seconds = 0;  // of the optimization steps
  bool stopped_by_time = false;
  double scene_extent = 0;       // m, the radius of the training camera centres
  std::vector<double> loss;      // per iteration
  double psnr_test_initial = 0;  // of the seeded model on the held-out views (0 without them)
  std::vector<splat::Exposure> exposures;  // per training view, in the order given ((1, 0) when not fitted)
  std::vector<TrainingSize> sizes;         // in the order trained
  // Where the time of a step went, s summed over the steps, in the order of the step's stages: each device
  // stage (splat::IterationStats::stage_ms), then "host" (the rest of the wall time: image preparation,
  // submission, exposure fits, densification).
  std::vector<std::pair<std::string, double>> stage_seconds;
};

// The exposure of each of `views` from the training views' (`train` in stamp order, `exposures` theirs):
// interpolated in time (splat::InterpolateExposure); empty `exposures`: none.
std::vector<splat::Exposure> ExposuresAt(const std::vector<StoredView>& views,
                                         const std::vector<StoredView>& train,
                                         const std::vector<splat::Exposure>& exposures);

// Adds the sky sphere of config.sky_gaussians Gaussians around the training cameras (splat/sky.h).
void AddSky(splat::GaussianModel& model, const std::vector<StoredView>& train, const SplatConfig& config);

// Trains `seed` on `train` (not empty); `test` is scored once before the first step. `device`:
// SplatRendererOptions::device.
Expected<SplatTrainingResult> TrainSplats(const splat::GaussianModel& seed,
                                          const std::vector<StoredView>& train,
                                          const std::vector<StoredView>& test, const SplatConfig& config,
                                          const std::string& device,
                                          const std::function<void(const TrainingProgress&)>& progress = {});

// Renders every view with the trainer's current model, in the view's exposure (exposures[i] for views[i];
// empty: the canonical one), and scores it against the real image; `renders` (optional) receives the first
// `keep` rendered views (their rgb in the view's exposure).
Expected<SplatScores> ScoreViews(splat::SplatTrainer& trainer, const std::vector<StoredView>& views,
                                 const std::vector<splat::Exposure>& exposures = {},
                                 std::vector<splat::RenderedView>* renders = nullptr, std::size_t keep = 0);

// Up to `count` views spread evenly over `views` (all of them when there are fewer).
std::vector<StoredView> SampleViews(const std::vector<StoredView>& views, std::size_t count);

}  // namespace uf::pipeline
