// `ultrafusion eval REFERENCE ESTIMATE`: evo-compatible trajectory accuracy (APE, RPE, KITTI drift), printed
// as a table and optionally written as JSON and PNG plots.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddEvalCommand(CLI::App& app);

}  // namespace uf::app
