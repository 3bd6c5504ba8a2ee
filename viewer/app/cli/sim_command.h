// `ultrafusion sim --scene NAME --out DIR [...]`: generates a simulated multi-sensor sequence with exact
// ground truth and controlled degradations (odometry/sim/sequence/sequence_generator.h lists the outputs).
// Settings come from the defaults, then the `sim:` section of --config, then the command-line options.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddSimCommand(CLI::App& app);

}  // namespace uf::app
