// `ultrafusion render SPLATS(.ply|.glb) --poses FILE --camera FILE --out DIR`: one EXR per pose (R G B A,
// Z depth, expected depth) and optional PNG previews, rendered headless on a Vulkan device (lavapipe on
// the CPU when there is no GPU).
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddRenderCommand(CLI::App& app);

}  // namespace uf::app
