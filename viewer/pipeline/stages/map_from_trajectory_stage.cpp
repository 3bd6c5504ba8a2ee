#include "viewer/pipeline/stages/map_from_trajectory_stage.h"

#include "mapping/deskew_with_trajectory.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"

namespace uf::pipeline {

Expected<MapFromTrajectoryOutput> RunMapFromTrajectory(const MapFromTrajectoryInput& in,
                                                       StageContext& context) {
  context.SetUnit("scans");
  const std::string file = (in.out / "trajectory.tum").string();
  Expected<Trajectory> read = ReadTrajectory(file);
  if (!read) return Status::Error(file + ": " + read.error());
  if (read->size() < 2 || !read->has_stamps())
    return Status::Error(file + ": needs at least two stamped poses");
  // The trajectory in the estimator's body frame, as the odometry stage would have left it.
  MapFromTrajectoryOutput out;
  const SE3 T_out_est = in.frames.T_output_estimator();
  out.estimated.stamps = read->stamps;
  for (const SE3& T_world_out : read->poses) out.estimated.poses.push_back(T_world_out * T_out_est);
  const SE3 T_est_lidar = in.frames.T_estimator_lidar();

  std::int64_t outside = 0;
  const Status status = ForEachMeasurement(*in.stream, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == in.sensors.lidar) {
      ++out.scans;
      std::optional<Keyframe> keyframe =
          mapping::DeskewWithTrajectory(*scan, out.estimated, T_est_lidar, in.min_range_m, in.max_range_m);
      if (!keyframe) {
        ++outside;
        return Status();
      }
      if (Status s = in.mapper->AddKeyframe(std::move(*keyframe)); !s.ok()) return s;
      ++out.keyframes_mapped;
      context.Progress(out.scans);
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data); frame && in.mapper->UsesCamera(m.stream)) {
      in.mapper->AddCameraFrame(m.stream, std::move(*frame));
    } else if (const auto* fix = std::get_if<GnssFix>(&m.data); fix && m.stream == in.sensors.gnss) {
      out.fixes.push_back(*fix);
    }
    return Status();
  });
  if (!status.ok()) return status;
  if (outside > 0)
    out.notes.push_back("--from map: " + std::to_string(outside) + " of " + std::to_string(out.scans) +
                        " scans lie outside trajectory.tum's time span and are not mapped");
  return out;
}

}  // namespace uf::pipeline
