#include "odometry/sim/sequence/sim_trajectory.h"

#include <cmath>

#include "odometry/io/trajectory_file.h"
#include "odometry/sim/scene/default_trajectory.h"

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
  Expected<Trajectory> poses =
      config.trajectory.file.empty()
          ? DefaultSceneTrajectory(config.scene, config.duration_s, config.seed, config.start_stamp)
          : ReadPoseFile(config);
  if (!poses) return poses.status();
  const Stamp knot_spacing = FromSeconds(config.trajectory.knot_spacing_s);
  auto spline = TrajectorySpline::FitPoses(*poses, knot_spacing);
  if (!spline) {
    const std::string where =
        config.trajectory.file.empty() ? "the default trajectory" : config.trajectory.file;
    return Status::Error(where + ": " + spline.error());
  }
  const Stamp begin = poses->stamps.front(), end = poses->stamps.back();
  return SimulationTrajectory{std::move(*poses), std::move(*spline), begin, end};
}

}  // namespace uf::sim
