#include "odometry/sim/sequence/sim_trajectory.h"

#include <algorithm>
#include <cmath>

#include "odometry/io/trajectory_file.h"
#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/scene/handheld_trajectory.h"

namespace uf::sim {
namespace {

SE3 KittiToBody(const SE3& T_kitti) {
  Eigen::Matrix3d C;
  C << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  const SE3 axes(SO3(C), Eigen::Vector3d::Zero());
  return axes * T_kitti * axes.inverse();
}

Expected<Trajectory> ReadPoseFile(const SimulationConfig& config) {
  const TrajectorySource& source = config.trajectory;
  auto format = ParseTrajectoryFormat(source.format);
  if (!format) return Status::Error("sim.trajectory.format: " + format.error());
  if (*format == TrajectoryFormat::kAuto) {
    format = DetectTrajectoryFormat(source.file);
    if (!format) return format.status();
  }
  auto poses = ReadTrajectory(source.file, *format);
  if (!poses) return poses.status();
  if (*format == TrajectoryFormat::kKitti) {
    for (SE3& pose : poses->poses) pose = KittiToBody(pose);
    if (!poses->has_stamps()) {
      const double step_ns = 1e9 / source.kitti_rate_hz;
      for (std::size_t i = 0; i < poses->size(); ++i)
        poses->stamps.push_back(config.start_stamp + std::llround(static_cast<double>(i) * step_ns));
    }
  }
  // At most duration_s of it.
  if (config.duration_s > 0.0 && poses->has_stamps()) {
    const Stamp last = poses->stamps.front() + FromSeconds(config.duration_s);
    std::size_t keep = 0;
    while (keep < poses->size() && poses->stamps[keep] <= last) ++keep;
    poses->stamps.resize(keep);
    poses->poses.resize(keep);
  }
  if (poses->size() < 4)
    return Status::Error(source.file + ": " + std::to_string(poses->size()) +
                         " poses in the simulated span; the trajectory spline needs at least 4");
  return poses;
}

}  // namespace

Expected<SimulationTrajectory> MakeSimulationTrajectory(const SimulationConfig& config) {
  Trajectory poses, scene_path;
  double knot_spacing_s = config.trajectory.knot_spacing_s;
  if (!config.trajectory.file.empty()) {
    Expected<Trajectory> read = ReadPoseFile(config);
    if (!read) return read.status();
    poses = std::move(*read);
  } else if (config.trajectory.motion == Motion::kHandheld) {
    Expected<HandheldTrajectory> handheld =
        HandheldSceneTrajectory(config.scene, config.duration_s, config.seed, config.start_stamp);
    if (!handheld) return handheld.status();
    poses = std::move(handheld->poses);
    scene_path = std::move(handheld->path);
    knot_spacing_s = std::min(knot_spacing_s, kHandheldKnotSpacingS);
  } else {
    Expected<Trajectory> driven =
        DefaultSceneTrajectory(config.scene, config.duration_s, config.seed, config.start_stamp);
    if (!driven) return driven.status();
    poses = std::move(*driven);
  }
  if (scene_path.empty()) scene_path = poses;
  auto spline = TrajectorySpline::FitPoses(poses, FromSeconds(knot_spacing_s));
  if (!spline) {
    const std::string where =
        config.trajectory.file.empty() ? "the default trajectory" : config.trajectory.file;
    return Status::Error(where + ": " + spline.error());
  }
  SimulationTrajectory out{std::move(poses), std::move(scene_path), std::move(*spline)};
  out.begin = out.poses.stamps.front();
  out.end = out.poses.stamps.back();
  for (std::size_t i = 0; i < out.poses.size(); ++i) {
    const SE3 fitted = out.spline.Pose(out.poses.stamps[i]);
    const SE3& given = out.poses.poses[i];
    out.fit_position_error_m =
        std::max(out.fit_position_error_m, (fitted.translation() - given.translation()).norm());
    out.fit_rotation_error_rad =
        std::max(out.fit_rotation_error_rad, (given.so3().inverse() * fitted.so3()).Log().norm());
  }
  return out;
}

}  // namespace uf::sim
