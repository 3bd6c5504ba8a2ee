#include "viewer/pipeline/stages/map_from_trajectory_stage.h"

#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"

namespace uf::pipeline {

std::optional<Keyframe> DeskewScan(const LidarScan& scan, const Trajectory& T_world_est, const SE3& T_est_lidar,
                                   double min_range_m, double max_range_m) {
  Keyframe keyframe;
  keyframe.stamp = scan.stamp + (scan.end - scan.stamp) / 2;
  const std::optional<SE3> middle = T_world_est.PoseAt(keyframe.stamp);
  if (!middle) return std::nullopt;
  keyframe.T_world_body = *middle;
  keyframe.scan_world.reserve(scan.points.size());
  keyframe.scan_intensity.reserve(scan.points.size());
  const SE3 T_world_lidar_middle = *middle * T_est_lidar;
  for (const LidarPoint& point : scan.points) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    const double range = p.norm();
    if (!p.allFinite() || range < min_range_m || range > max_range_m) continue;
    std::optional<SE3> T_world_est_point = middle;
    if (scan.has_point_times) T_world_est_point = T_world_est.PoseAt(scan.stamp + point.offset_ns);
    if (!T_world_est_point) continue;
    const SE3 T_world_lidar = scan.has_point_times ? *T_world_est_point * T_est_lidar : T_world_lidar_middle;
    keyframe.scan_world.push_back((T_world_lidar * p).cast<float>());
    keyframe.scan_intensity.push_back(point.intensity);
  }
  return keyframe;
}

Expected<MapFromTrajectoryOutput> RunMapFromTrajectory(const MapFromTrajectoryInput& in, StageContext& context) {
  context.SetUnit("scans");
  const std::string file = (in.out / "trajectory.tum").string();
  Expected<Trajectory> read = ReadTrajectory(file);
  if (!read) return Status::Error(file + ": " + read.error());
  if (read->size() < 2 || !read->has_stamps()) return Status::Error(file + ": needs at least two stamped poses");
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
          DeskewScan(*scan, out.estimated, T_est_lidar, in.min_range_m, in.max_range_m);
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
