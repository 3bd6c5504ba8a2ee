// `ultrafusion splat RUN_DIR`: Gaussian splats trained on a run's keyframe images, seeded from its map and
// placed by its trajectory (splat_job.h); writes splats.ply, splats.glb, metrics.json, comparisons/ and
// plots/splat_loss.png into the run folder.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddSplatCommand(CLI::App& app);

}  // namespace uf::app
