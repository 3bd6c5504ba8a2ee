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

#include <string>

#include "viewer/pipeline/stages/run_stages.h"

namespace uf::app {

// Why the splat stage cannot run on this dataset ("" when it can): no camera stream, or a camera without
// intrinsics or extrinsic.
std::string SplatSkipReason(const DatasetDescription& description, const std::string& output_frame);

Status RunSplatStage(RunState& state, StageContext& context);
Status RunViewsStage(RunState& state, StageContext& context);

}  // namespace uf::app
