#include "viewer/pipeline/run/run_frames.h"

#include "odometry/io/dataset_sensors.h"

namespace uf::pipeline {
namespace {

template <typename Enum, std::size_t N>
std::optional<Enum> Parse(std::string_view text, const std::array<Enum, N>& values) {
  for (Enum value : values)
    if (Name(value) == text) return value;
  return std::nullopt;
}

// T_lidar0_lidar(t) -> T_imu0_imu(t) = T_imu_lidar * T_lidar0_lidar(t) * T_imu_lidar^-1: the IMU's pose in a
// world that is the IMU frame at the start.
Trajectory ToImuFrame(const Trajectory& lidar_trajectory, const SE3& T_imu_lidar) {
  Trajectory imu;
  imu.stamps = lidar_trajectory.stamps;
  imu.poses.reserve(lidar_trajectory.size());
  const SE3 T_lidar_imu = T_imu_lidar.inverse();
  for (const SE3& T_lidar0_lidar : lidar_trajectory.poses)
    imu.poses.push_back(T_imu_lidar * T_lidar0_lidar * T_lidar_imu);
  return imu;
}

// T_world_imu(t) -> T_world_lidar(t) = T_world_imu(t) * T_imu_lidar, in the same world.
Trajectory ToLidarFrame(const Trajectory& imu_trajectory, const SE3& T_imu_lidar) {
  Trajectory lidar;
  lidar.stamps = imu_trajectory.stamps;
  lidar.poses.reserve(imu_trajectory.size());
  for (const SE3& T_world_imu : imu_trajectory.poses) lidar.poses.push_back(T_world_imu * T_imu_lidar);
  return lidar;
}

// T_S_B for the sensor S that `frame` names (the first LiDAR or IMU stream): its T_body_sensor inverted,
// the identity when it has none or there is no such stream (the body is then that sensor, as ImuFromSensor
// and the estimator take it).
SE3 SensorFromBody(const DatasetDescription& description, const DatasetSensors& sensors,
                   TrajectoryFrame frame) {
  const int stream = frame == TrajectoryFrame::kImu ? sensors.imu : sensors.lidar;
  if (stream < 0) return SE3();
  const std::optional<SE3>& T_body_sensor =
      description.streams[static_cast<std::size_t>(stream)].T_body_sensor;
  return T_body_sensor ? T_body_sensor->inverse() : SE3();
}

}  // namespace

std::string_view Name(OdometryMode mode) {
  return mode == OdometryMode::kLio ? "lio" : mode == OdometryMode::kWio ? "wio" : "lo";
}
std::string_view Name(TrajectoryFrame frame) { return frame == TrajectoryFrame::kImu ? "imu" : "lidar"; }
std::string_view Name(MapSource source) {
  return source == MapSource::kTrajectory ? "trajectory" : "odometry";
}

std::optional<OdometryMode> ParseOdometryMode(std::string_view text) {
  return Parse(text, std::array{OdometryMode::kLo, OdometryMode::kLio, OdometryMode::kWio});
}
std::optional<TrajectoryFrame> ParseTrajectoryFrame(std::string_view text) {
  return Parse(text, std::array{TrajectoryFrame::kLidar, TrajectoryFrame::kImu});
}
std::optional<MapSource> ParseMapSource(std::string_view text) {
  return Parse(text, std::array{MapSource::kOdometry, MapSource::kTrajectory});
}

TrajectoryFrame EstimatorFrame(OdometryMode mode) {
  return mode == OdometryMode::kLo ? TrajectoryFrame::kLidar : TrajectoryFrame::kImu;
}

SE3 RunFrames::T_estimator_lidar() const { return mode == OdometryMode::kLio ? *T_imu_lidar : SE3(); }

SE3 RunFrames::T_output_estimator() const {
  if (trajectory_frame == EstimatorFrame(mode)) return SE3();
  return trajectory_frame == TrajectoryFrame::kImu ? *T_imu_lidar : T_imu_lidar->inverse();
}

Trajectory RunFrames::OutputTrajectory(const Trajectory& estimated) const {
  if (trajectory_frame == EstimatorFrame(mode)) return estimated;
  return trajectory_frame == TrajectoryFrame::kImu ? ToImuFrame(estimated, *T_imu_lidar)
                                                   : ToLidarFrame(estimated, *T_imu_lidar);
}

void RunFrames::SetImuFromLidar(const SE3& T) {
  T_imu_lidar = T;
  // F = LiDAR, E = IMU: T_F_B = T_lidar_imu T_E_B.
  if (trajectory_frame == TrajectoryFrame::kLidar && mode == OdometryMode::kLio)
    T_output_body = T.inverse() * T_estimator_body;
}

Expected<RunFrames> ResolveRunFrames(const DatasetDescription& description, OdometryMode mode,
                                     TrajectoryFrame trajectory_frame, MapSource map_from) {
  const DatasetSensors sensors = FindSensors(description);
  if (sensors.lidar < 0 && (mode != OdometryMode::kWio || trajectory_frame == TrajectoryFrame::kLidar))
    return Status::Error(description.path.string() + ": no LiDAR stream");
  RunFrames frames;
  frames.mode = mode;
  frames.trajectory_frame = trajectory_frame;
  frames.map_from = map_from;
  frames.T_imu_lidar = sensors.T_imu_lidar;
  const bool lio = mode == OdometryMode::kLio;
  if ((lio || trajectory_frame != EstimatorFrame(mode)) && !frames.T_imu_lidar)
    return Status::Error(description.path.string() + ": no LiDAR-to-IMU transform (T_body_sensor of " +
                         description.streams[static_cast<std::size_t>(sensors.lidar)].name + ")");
  frames.T_estimator_body = SensorFromBody(description, sensors, EstimatorFrame(mode));
  frames.T_output_body = SensorFromBody(description, sensors, trajectory_frame);
  // T_M_W = T_lidar_imu for an LO run written in the IMU frame whose map came from the odometry, where
  // T_imu_lidar = T_F_B(imu) * T_B_lidar (ImuFromSensor).
  if (mode == OdometryMode::kLo && trajectory_frame == TrajectoryFrame::kImu &&
      map_from == MapSource::kOdometry) {
    const StreamInfo& lidar = description.streams[static_cast<std::size_t>(sensors.lidar)];
    frames.T_map_world = (frames.T_output_body * *lidar.T_body_sensor).inverse();
  }
  return frames;
}

}  // namespace uf::pipeline
