// `ultrafusion colorize SCAN IMAGE --intrinsics FILE --extrinsic FILE --out FILE.ply [--overlay FILE.png]`:
// colours one LiDAR scan from one camera image (a calibration check), prints how many points inside the
// image footprint took a colour and the edge-alignment score of the extrinsic, and writes the coloured
// points as PLY and optionally the image with the projected depth drawn on it.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddColorizeCommand(CLI::App& app);

}  // namespace uf::app
