// The camera's files of a run with the camera in the estimator (V modes): tracks.csv, the track plots and
// the overlays (plots/tracks_<stamp ns>.png), as `ultrafusion track` writes them (track/track_job.h), from
// the frames the estimator tracked.
#pragma once

#include <filesystem>

#include "viewer/pipeline/run/run_pipeline.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/stages/odometry_stage.h"

namespace uf::pipeline {

// Nothing without tracked frames; errors: a file that cannot be written.
Status WriteRunTracks(const RunPlan& plan, const OdometryStageOutput& odometry,
                      const std::filesystem::path& out, StageContext& context);

}  // namespace uf::pipeline
