// `ultrafusion info DATASET [--json]`: what a dataset holds (streams, kinds, counts, rates, stamps,
// LiDAR per-point time field, IMU unit) and whether its time stamps can be trusted (gaps, backwards or
// duplicate stamps, out-of-order messages, rate jitter), with a verdict per stream.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddInfoCommand(CLI::App& app);

}  // namespace uf::app
