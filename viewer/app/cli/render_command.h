// `ultrafusion render`: one EXR per pose (R G B A, Z depth, expected depth) and optional PNG previews,
// rendered headless on a Vulkan device (lavapipe on the CPU when there is no GPU), in two forms:
//   render SPLATS(.ply|.glb) --poses FILE --camera FILE --out DIR   poses T_world_camera, a camera file
//   render RUN_DIR --stamps FILE [--camera NAME] --out DIR          a run's splats through its camera at
//                                                                   those times (run_render_inputs.h)
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddRenderCommand(CLI::App& app);

}  // namespace uf::app
