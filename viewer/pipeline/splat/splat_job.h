// Splat training for one run folder, start to end, shared by `ultrafusion splat RUN_DIR` and run's splat
// stage: run.json and config.yaml say which dataset to read again and how; the Gaussians are seeded from
// map.vdb; the first camera stream's keyframe images are placed on trajectory.tum (or --poses) and split into
// training and held-out views (splat_views.h); training (splat_training.h); then splats.ply, splats.glb,
// comparisons/, plots/splat_loss.png and metrics.json (splat_outputs.h). Nothing is written before training
// has succeeded.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "viewer/app/config/splat_config.h"
#include "viewer/pipeline/splat/splat_outputs.h"
#include "viewer/pipeline/splat/splat_views.h"

namespace uf::pipeline {

using app::SplatConfig;

struct SplatJobOptions {
  SplatConfig config;
  std::string device;  // SplatRendererOptions::device ("": a GPU if any, else lavapipe)
  std::string poses;   // TUM file of T_W_F to use instead of RUN_DIR/trajectory.tum; "": the run's
};

struct SplatJobCallbacks {
  // phase ("images", "train", "score"), items done, total (<= 0: unknown), unit text.
  std::function<void(const std::string&, std::int64_t, std::int64_t, const std::string&)> progress;
  std::function<void(const std::string&)> warning;  // e.g. uncoloured map points seeded grey
};

struct SplatJobResult {
  SplatMetrics metrics;
  std::vector<std::string> files;  // written, relative to the run folder
  std::vector<StoredView> test;    // the held-out views (camera, stamp, image)
  // The camera's own model (native resolution, distortion); the training pinhole shares its centre and axes.
  std::shared_ptr<const CameraModel> model;
};

Expected<SplatJobResult> RunSplatJob(const std::filesystem::path& run_dir, const SplatJobOptions& options,
                                     const SplatJobCallbacks& callbacks = {});

}  // namespace uf::pipeline
