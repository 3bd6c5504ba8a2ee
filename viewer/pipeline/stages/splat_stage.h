// The splat stages of `ultrafusion run`, after the map's exports:
//   splat  Gaussian splats trained on the run's keyframe images (splat_job.h, as `ultrafusion splat RUN_DIR`
//          does it, with the run's splat: config section): splats.ply, splats.glb, metrics.json,
//          comparisons/, plots/splat_loss.png; the report's splat section
//   views  the trained splats rendered at the held-out images' poses through the camera's own model (native
//          size, lens distortion as `ultrafusion render` applies it): views/<stamp_ns>.exr (R G B A, Z,
//          depth.expected) and .png, with views/poses.tum (T_world_camera, map frame) and, for a
//          pinhole-radtan camera, views/camera.yaml, so `ultrafusion render splats.ply --poses
//          views/poses.tum --camera views/camera.yaml` renders them again.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "viewer/pipeline/splat/splat_job.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

// Why the splat stage cannot run on this dataset ("" when it can): no camera stream, or a camera without
// intrinsics or extrinsic. T_output_body: T_F_B of the run (run_frames.h).
std::string SplatSkipReason(const DatasetDescription& description, const SE3& T_output_body);

struct SplatStageOutput {
  SplatJobResult result;
  std::vector<std::string> notes;  // the job's warnings
};

// `device`: the Vulkan device (SplatRendererOptions::device; "": a GPU if any, else lavapipe), as both
// stages take it.
Expected<SplatStageOutput> RunSplatStage(const std::filesystem::path& out, const app::SplatConfig& config,
                                         const std::string& device, StageContext& context);

// Renders the held-out views of `splat` into out/views/; returns the report's line on them.
Expected<std::string> RunViewsStage(const std::filesystem::path& out, const SplatJobResult& splat,
                                    const Eigen::Vector3f& background, const std::string& device,
                                    StageContext& context);

}  // namespace uf::pipeline
