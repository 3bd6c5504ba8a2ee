#include "viewer/pipeline/run/run_tracks.h"

#include "odometry/estimator/schedule/camera_degeneracy.h"
#include "viewer/pipeline/track/track_job.h"

namespace uf::pipeline {

Status WriteRunTracks(const RunPlan& plan, const OdometryStageOutput& odometry,
                      const std::filesystem::path& out, StageContext& context) {
  if (odometry.tracked_frames.empty()) return {};
  const StreamInfo& camera =
      plan.stream->description().streams[static_cast<std::size_t>(plan.sensors.camera)];
  TrackResult tracks;
  tracks.camera_stream = camera.name;
  tracks.width = camera.camera_model->width();
  tracks.height = camera.camera_model->height();
  tracks.max_features = plan.visual_config().tracker.max_features;
  tracks.frames = odometry.tracked_frames;
  for (const estimator::FrameTrackStats& stats : tracks.frames)
    tracks.degeneracy.push_back(
        estimator::ScoreCameraFrame(stats.tracked, stats.grid_occupancy, stats.epipolar_error_px));
  tracks.stereo.resize(tracks.frames.size());
  tracks.overlays = odometry.overlays;
  Expected<std::vector<std::string>> written = WriteTrackOutputs(out, tracks);
  if (!written) return written.status();
  for (const std::string& file : *written) context.AddOutput(file);
  return {};
}

}  // namespace uf::pipeline
