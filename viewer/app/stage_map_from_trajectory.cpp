#include "viewer/app/stage_map_from_trajectory.h"

#include <algorithm>

#include "mapping/deskew_with_trajectory.h"
#include "odometry/io/trajectory_file.h"
#include "viewer/app/run_map_stage.h"

namespace uf::app {
namespace {

// T_out_est: the estimator's body in the run's output frame (see the header).
SE3 OutputFromEstimator(const RunState& state) {
  const bool out_imu = state.output_frame == "imu";
  if (out_imu == state.lio) return SE3();
  return out_imu ? *state.sensors.T_imu_lidar : state.sensors.T_imu_lidar->inverse();
}

}  // namespace

Status RunMapFromTrajectoryStage(RunState& state, StageContext& context) {
  context.SetUnit("scans");
  const std::string file = (state.out / "trajectory.tum").string();
  Expected<Trajectory> read = ReadTrajectory(file);
  if (!read) return Status::Error(file + ": " + read.error());
  if (read->size() < 2 || !read->has_stamps())
    return Status::Error(file + ": needs at least two stamped poses");
  // The trajectory in the estimator's body frame, as the odometry stage would have left it.
  const SE3 T_out_est = OutputFromEstimator(state);
  state.estimated.stamps = read->stamps;
  state.estimated.poses.clear();
  for (const SE3& T_world_out : read->poses) state.estimated.poses.push_back(T_world_out * T_out_est);
  const SE3 T_est_lidar = state.lio ? *state.sensors.T_imu_lidar : SE3();

  std::int64_t scans = 0, outside = 0;
  while (true) {
    Expected<std::optional<Measurement>> next = state.stream->Next();
    if (!next) return next.status();
    if (!next->has_value()) break;
    Measurement& m = **next;
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == state.sensors.lidar) {
      ++scans;
      std::optional<Keyframe> keyframe = mapping::DeskewWithTrajectory(*scan, state.estimated, T_est_lidar,
                                                                       state.min_range_m, state.max_range_m);
      if (!keyframe) {
        ++outside;
        continue;
      }
      if (Status s = state.mapper->AddKeyframe(std::move(*keyframe)); !s.ok()) return s;
      ++state.keyframes_mapped;
      context.Progress(scans);
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data); frame && state.mapper->UsesCamera(m.stream)) {
      state.mapper->AddCameraFrame(m.stream, std::move(*frame));
    } else if (const auto* fix = std::get_if<GnssFix>(&m.data); fix && m.stream == state.sensors.gnss) {
      state.fixes.push_back(*fix);
    }
  }
  if (outside > 0)
    state.report.notes.push_back("--from map: " + std::to_string(outside) + " of " + std::to_string(scans) +
                                 " scans lie outside trajectory.tum's time span and are not mapped");
  state.report.scans = scans;
  state.report.keyframes = static_cast<std::int64_t>(state.estimated.size());
  return RunMapStage(state, context);
}

}  // namespace uf::app
