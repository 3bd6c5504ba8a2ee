#include "viewer/pipeline/splat/splat_camera_poses.h"

#include <algorithm>

namespace uf::app {
namespace {

// The first stream of `kind`, or nullptr.
const StreamInfo* FirstStream(const DatasetDescription& description, SensorKind kind) {
  for (const StreamInfo& stream : description.streams)
    if (stream.kind == kind) return &stream;
  return nullptr;
}

}  // namespace

Expected<SE3> OutputFrameFromBody(const DatasetDescription& description, const std::string& output_frame) {
  if (output_frame == "imu") {
    const StreamInfo* imu = FirstStream(description, SensorKind::kImu);
    return imu && imu->T_body_sensor ? imu->T_body_sensor->inverse() : SE3();
  }
  if (output_frame != "lidar")
    return Status::Error("output frame '" + output_frame + "': expected lidar or imu");
  const StreamInfo* lidar = FirstStream(description, SensorKind::kLidar);
  if (!lidar) return Status::Error(description.path.string() + ": no LiDAR stream (the trajectory's frame)");
  if (!lidar->T_body_sensor) {
    // Without a LiDAR extrinsic the body frame is the LiDAR's (EstimatorFromBody takes it so).
    return SE3();
  }
  return lidar->T_body_sensor->inverse();
}

Expected<SE3> MapFromTrajectoryWorld(const DatasetDescription& description, const std::string& mode,
                                     const std::string& output_frame, bool from_trajectory) {
  if (from_trajectory || mode != "lo" || output_frame != "imu") return SE3();
  // T_imu_lidar = T_F_B(imu) * T_B_lidar (odometry/io/dataset_sensors.h ImuFromLidar), so T_M_W =
  // T_lidar_imu.
  const StreamInfo* lidar = FirstStream(description, SensorKind::kLidar);
  if (!lidar || !lidar->T_body_sensor)
    return Status::Error(description.path.string() + ": no LiDAR T_body_sensor, which an LO run written " +
                         "in the IMU frame needs");
  Expected<SE3> T_imu_body = OutputFrameFromBody(description, "imu");
  if (!T_imu_body) return T_imu_body.status();
  return (*T_imu_body * *lidar->T_body_sensor).inverse();
}

}  // namespace uf::app
