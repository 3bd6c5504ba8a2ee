// A new LiDAR extrinsic applied to a running window (see lidar_odometry.h, SetLidarExtrinsic), and its
// translation estimated in the window (lio.estimate_lidar_translation); docs/METHOD.md "Online
// spatiotemporal calibration".
#include <ceres/normal_prior.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {
namespace {

constexpr long kLidarTranslationPriorTag = -1;

}  // namespace

// The block, and its prior r = (t_BL - t_given) / sigma (again after the graph was cleared: the block keeps
// its value).
void LidarOdometry::Impl::AttachLidarTranslation() {
  if (!EstimatesLidarTranslation()) return;
  graph.AddEuclideanBlock(lidar_translation.data(), 3);
  const ceres::Matrix A = ceres::Matrix::Identity(3, 3) / config.lidar_translation_sigma_m;
  const ceres::Vector b = given_lidar_translation;
  graph.Add(FactorKind::kStatePrior, kLidarTranslationPriorTag, std::make_unique<ceres::NormalPrior>(A, b),
            nullptr, {lidar_translation.data()});
}

// Whether the window's orientations show every direction of the lever arm. Between nodes j and k the LiDAR
// moves by R_k t_BL - R_j t_BL besides the IMU's motion; with R_k = R_0 Exp(theta_k) and small turns that
// is R_0 [theta_j - theta_k]x t_BL: a lever arm along the turns' axis is unseen. Over the window, with
// theta_k centred on their mean,
//   S = 1/n sum_k ( |theta_k|^2 I - theta_k theta_k^T )   (= 1/n sum_k [theta_k]x^T [theta_k]x)
// is the information the turns give t_BL (up to the LiDAR's noise); its smallest eigenvalue must reach
// lidar_translation_min_turn_deg^2: turning 1 deg RMS about two axes gives 1 deg^2 along the third. All or
// nothing: a car's yaw shows x and y, but freeing them alone moved the estimate at every corner, and the
// body's poses with it against a map built with the old value (docs/METHOD.md).
bool LidarOdometry::Impl::LeverExcited() const {
  const long n = LastNodeId() - first_node_id + 1;
  if (n < 3) return false;
  const SO3 R0 = NodePose(first_node_id).so3();
  std::vector<Eigen::Vector3d> theta;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (long id = first_node_id; id <= LastNodeId(); ++id) {
    theta.push_back((R0.inverse() * NodePose(id).so3()).Log());
    mean += theta.back() / static_cast<double>(n);
  }
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& t : theta) {
    const Eigen::Vector3d c = t - mean;
    S += (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose()) / static_cast<double>(n);
  }
  const double min_turn = config.lidar_translation_min_turn_deg * std::numbers::pi / 180;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues()(0) >= min_turn * min_turn;
}

// With the translation estimated, a keyframe whose body pose was computed with a translation that may still
// move waits: until the estimate has settled (LeverSettled), at most kMaxLeverHeld keyframes (then the
// oldest leave), or the end of the run. Its LiDAR pose is what the map measured, so on release the body
// moves as in SetLidarExtrinsic: T_WB' = T_WB T_BL_then T_BL_now^-1 = T_WB (I, u - t) for the translations
// u then and t now (the rotation is the same). Its points (world) and velocity stay (the velocity's
// lever-arm share, omega x R (u - t), is left out). Keyframe::lidar_translation keeps the value it left the
// window with.
void LidarOdometry::Impl::Emit(Keyframe keyframe) {
  if (!EstimatesLidarTranslation()) {
    finished.push_back(std::move(keyframe));
    return;
  }
  held_for_lever.push_back({std::move(keyframe), config.T_body_lidar.translation()});
  ReleaseLeverHeld(LeverSettled());
}

// Settled: over its last kLeverSettleSolves free window solves it stayed within kLeverSettledM of where it
// is now (a hand-held 32-beam LiDAR gets there 2-3 s after the first free solve, a 16-beam one later).
bool LidarOdometry::Impl::LeverSettled() const {
  if (recent_lever.size() < kLeverSettleSolves) return false;
  const Eigen::Vector3d t = config.T_body_lidar.translation();
  return std::all_of(recent_lever.begin(), recent_lever.end(),
                     [&t](const Eigen::Vector3d& r) { return (r - t).norm() <= kLeverSettledM; });
}

void LidarOdometry::Impl::ReleaseLeverHeld(bool all) {
  const Eigen::Vector3d t = config.T_body_lidar.translation();
  while (!held_for_lever.empty() && (all || held_for_lever.size() > kMaxLeverHeld)) {
    LeverHeldKeyframe& held = held_for_lever.front();
    held.keyframe.T_world_body = held.keyframe.T_world_body * SE3(SO3(), held.lidar_translation - t);
    finished.push_back(std::move(held.keyframe));
    held_for_lever.pop_front();
  }
}

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
  const Eigen::Vector3d t_BL = T_body_lidar.translation();  // the estimated one restarts from it
  std::copy(t_BL.data(), t_BL.data() + 3, lidar_translation.begin());
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
