// The files splat training writes into a run folder, each atomically (a temporary name renamed into place,
// so nothing is left under a final name on failure):
//   splats.ply (3DGS PLY), splats.glb (KHR_gaussian_splatting), metrics.json (SplatMetrics, below),
//   comparisons/<stamp_ns>_render.png, _real.png, _compare.png (real | rendered side by side) and
//   <stamp_ns>.exr (export/exr_view.h) for the first held-out views, and plots/splat_loss.png.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"
#include "splat/render_types.h"
#include "viewer/pipeline/splat/splat_training.h"

namespace uf::pipeline {

// metrics.json. Keys: psnr_test, ssim_test (means over the held-out views, dB / [0, 1]),
// psnr_test_initial (the seeded model, before training: how well the map and the poses line up),
// psnr_train, ssim_train (over up to 16 training views), iterations, iterations_planned, iterations_per_s,
// seconds, stopped_by ("iterations" or "time_budget"), gaussians, gaussians_initial (map seeds + feature
// seeds + sky), map_seeds, feature_seeds (viewer/pipeline/splat/feature_seeds.h), sky_gaussians,
// uncoloured_seeds, unseen_map_points (uncoloured, not seeded: splat/seeding.h), device, camera, resolution
// [w, h], views_train, views_test, images, images_outside_trajectory, images_undecodable, masked_pixels (of
// the training resolution: not trained on nor scored), scene_extent_m, sh_degree, test_views [{stamp_ns,
// psnr, ssim}], exposure_compensation, exposures [{stamp_ns, held_out, gain [r, g, b], bias [r, g, b]}]
// (every view in stamp order; fitted for the training views, interpolated for the held-out ones; empty
// without compensation), stage_seconds {stage: s} (where the training time went, summed over the steps:
// SplatTrainingResult::stage_seconds), sizes [{resolution [w, h], iterations, seconds, iterations_per_s}]
// (the steps at each training size in order: one entry, or one per size of coarse to fine).
struct ViewExposure {
  Stamp stamp = 0;
  bool held_out = false;
  splat::Exposure exposure;
};

struct SplatMetrics {
  SplatScores test, train;
  double psnr_test_initial = 0;
  int iterations = 0, iterations_planned = 0;
  double seconds = 0;
  bool stopped_by_time = false;
  std::size_t gaussians = 0, gaussians_initial = 0, map_seeds = 0, sky_gaussians = 0, uncoloured_seeds = 0;
  std::size_t unseen_map_points = 0, feature_seeds = 0;
  std::string device, camera;
  int width = 0, height = 0;
  std::size_t views_train = 0, views_test = 0;
  std::int64_t images = 0, images_outside_trajectory = 0, images_undecodable = 0;
  std::size_t masked_pixels = 0;
  double scene_extent_m = 0;
  int sh_degree = 0;
  bool exposure_compensation = false;
  std::vector<ViewExposure> exposures;
  std::vector<std::pair<std::string, double>> stage_seconds;  // SplatTrainingResult::stage_seconds
  std::vector<TrainingSize> sizes;                            // SplatTrainingResult::sizes

  double iterations_per_s() const { return seconds > 0 ? iterations / seconds : 0.0; }
};

Status WriteSplatMetrics(const std::filesystem::path& file, const SplatMetrics& metrics);

// splats.ply and splats.glb in `folder`; returns their names.
Expected<std::vector<std::string>> WriteSplatFiles(const std::filesystem::path& folder,
                                                   const splat::GaussianModel& model);

// 8-bit PNG of a width x height x 3 image in [0, 1] (clamped).
Status WriteRgbPng(const std::filesystem::path& file, const std::vector<float>& rgb, int width, int height);

// comparisons/ for each rendered held-out view (renders[i] belongs to views[i]); returns the files written,
// relative to `folder`.
Expected<std::vector<std::string>> WriteComparisons(const std::filesystem::path& folder,
                                                    const std::vector<StoredView>& views,
                                                    const std::vector<splat::RenderedView>& renders);

// plots/splat_loss.png: the training loss per iteration (none for fewer than two iterations).
Expected<std::vector<std::string>> WriteLossPlot(const std::filesystem::path& folder,
                                                 const std::vector<double>& loss);

}  // namespace uf::pipeline
