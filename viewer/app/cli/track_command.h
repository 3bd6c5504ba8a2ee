// `ultrafusion track DATASET [--out DIR]`: the visual front end over one camera stream of a dataset
// (viewer/pipeline/track/track_job.h), to check a camera or a recording before a drive. Prints per-frame
// figures summed up (features, tracked ratio, grid occupancy, epipolar error, time per frame, poor and
// skipped frames); writes tracks.csv, plots and track overlays with --out.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddTrackCommand(CLI::App& app);

}  // namespace uf::app
