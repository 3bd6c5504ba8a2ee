// A new LiDAR extrinsic applied to a running window (see lidar_odometry.h, SetLidarExtrinsic; docs/METHOD.md
// "Online spatiotemporal calibration").
#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {

// The LiDAR poses are what the map measured, so they stay: every body pose moves to
// T_WB_new = T_WB_old * T_BL_old * T_BL_new^-1, which gives T_WB_new * T_BL_new = T_WB_old * T_BL_old.
// The map (built from LiDAR poses) is unchanged; the point-to-plane factors, which carry T_BL in their
// points, are rebuilt against it. The marginalization prior was linearized at the old body poses, so it
// is dropped (as in ApplyInertialAlignment): the oldest pose then holds the gauge until the next
// marginalization makes a new prior. Velocities and biases are kept; the lever arm's share of the velocity
// (omega x the change of the IMU's position relative to the LiDAR) is left to the next solve. Gravity moves
// in the world (SetWorldGravity), and the IMU factors are made again with it.
void LidarOdometry::Impl::SetLidarExtrinsic(const SE3& T_body_lidar) {
  const SE3 delta = config.T_body_lidar * T_body_lidar.inverse();
  config.T_body_lidar = T_body_lidar;
  for (long id = first_node_id; id <= LastNodeId(); ++id) NodeAt(id).pose = PoseBlock(NodePose(id) * delta);
  if (last_registered) last_registered->pose = last_registered->pose * delta;
  restart_pose = restart_pose * delta;
  graph.DropPrior();
  for (ScanState& scan : window)
    if (graph.Count(FactorKind::kLidar, scan.id) > 0) Associate(scan);
  if (!inertial) return;  // the initialization will align the world with gravity at the new extrinsic
  SetWorldGravity();
  for (long id = first_node_id + 1; id <= LastNodeId(); ++id) {
    if (graph.Count(FactorKind::kImu, id) == 0) continue;
    Expected<ImuPreintegration> pre =
        imu.Preintegrate(NodeAt(id - 1).stamp, NodeAt(id).stamp, NodeAt(id - 1).speed_bias.data());
    if (!pre) continue;  // keeps the factor it has (the samples were there when it was made)
    graph.Remove(FactorKind::kImu, id);
    AddImuFactor(id, std::make_unique<ImuFactor>(std::move(*pre)));
  }
}

// Where gravity lies in the window's world. The initialization aligned the world with gravity through the
// IMU (R_WI0, its orientation then) while the map took the LiDAR at R_WI0 R_IL0 (the extrinsic then). With
// the extrinsic R_IL now, the map's world is the gravity-aligned one turned by
//   E = R_WI0 R_IL0 R_IL^T R_WI0^T
// (the LiDAR's orientation in the map over the one the IMU's gravity and R_IL give it), so g_world =
// E (0, 0, -gravity); E = I until the extrinsic changes. The world is not turned back instead: the map, and
// the poses that already left the window, are in it.
void LidarOdometry::Impl::SetWorldGravity() {
  Eigen::Vector3d g(0.0, 0.0, -config.imu.gravity);
  if (gravity_reference) {
    const SO3& R0 = gravity_reference->R_world_imu;
    g = (R0 * gravity_reference->R_imu_lidar * config.T_body_lidar.so3().inverse() * R0.inverse()) * g;
  }
  imu.SetGravityWorld(g);
}

Status LidarOdometry::SetLidarExtrinsic(const SE3& T_body_lidar) {
  if (!impl_->config.use_imu)
    return Status::Error("SetLidarExtrinsic: LO has no extrinsic (its body is the LiDAR)");
  if (impl_->gnss)
    return Status::Error(
        "SetLidarExtrinsic: not with GNSS factors (the world would tilt from gravity, which the GNSS "
        "alignment, yaw only, needs)");
  if (!T_body_lidar.matrix().allFinite())
    return Status::Error("SetLidarExtrinsic: the extrinsic is not finite");
  impl_->SetLidarExtrinsic(T_body_lidar);
  return {};
}

Trajectory LidarOdometry::WindowPoses() const {
  Trajectory poses;
  for (long id = impl_->first_node_id; id <= impl_->LastNodeId(); ++id) {
    poses.stamps.push_back(impl_->NodeAt(id).stamp);
    poses.poses.push_back(impl_->NodePose(id));
  }
  return poses;
}

}  // namespace uf::estimator
