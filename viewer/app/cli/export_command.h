// `ultrafusion export RUN_DIR --format ply,las,glb`: writes the map of a run folder (map.vdb) again, in the
// chosen formats and frame (local, or ENU / UTM when the map is georeferenced).
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddExportCommand(CLI::App& app);

}  // namespace uf::app
