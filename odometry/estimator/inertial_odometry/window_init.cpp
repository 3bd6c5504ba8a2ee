// Initialization of the wheel-inertial window and its restarts (see inertial_window.h).
#include <numbers>
#include <sstream>

#include "odometry/estimator/factors/bias_prior_factor.h"
#include "odometry/estimator/factors/imu_factor.h"
#include "odometry/estimator/inertial_odometry/inertial_window.h"

namespace uf::estimator {

// Once init_window_nodes nodes wait: their poses dead-reckoned from the wheel, then the alignment (Align).
// A failed window drops its oldest node and waits for the next; the first failure is logged.
void InertialOdometry::Impl::TryInitialize() {
  if (static_cast<int>(init_stamps.size()) < config.init_window_nodes) return;
  Expected<std::vector<SE3>> poses = DeadReckon(init_stamps);
  Expected<InertialAlignment> alignment = poses ? Align(*poses) : Expected<InertialAlignment>(poses.status());
  const Status failure = alignment ? Start(*alignment, *poses) : alignment.status();
  if (failure.ok()) {
    std::ostringstream summary;
    // LidarAidedAlignment is generic on the poses: here they are the wheel's or the camera's.
    summary << (alignment->mode == "lidar-aided" ? "wheel-aided" : alignment->mode) << " at "
            << StampText(nodes.back().stamp) << " (gravity estimate " << alignment->gravity_estimate
            << " m/s^2, gyro bias " << alignment->gyro_bias.transpose() << ")";
    init_summary = summary.str();
    return;
  }
  if (last_init_failure.empty())
    warnings.push_back("WIO initialization deferred at " + StampText(init_stamps.back()) + ": " +
                       failure.message());
  last_init_failure = failure.message();
  init_stamps.erase(init_stamps.begin());
  TrimStreams();
}

// The alignment of the waiting nodes: the static one, else the moving one on the wheel's poses
// (init/inertial_alignment.h). Without the wheel the IMU alone takes a constant velocity for rest: the static
// alignment runs when the camera sees the rest too, else the visual-inertial one (mode D), which replaces
// `poses` by the camera's and the IMU's.
Expected<InertialAlignment> InertialOdometry::Impl::Align(std::vector<SE3>& poses) {
  if (visual && !config.use_wheel)
    if (std::optional<std::string> moving = visual->NotStillReason(init_stamps)) {
      Expected<InertialAlignment> alignment = VisualInertialAlignment(poses);
      if (!alignment) return Status::Error(*moving + "; " + alignment.status().message());
      return alignment;
    }
  return AlignStaticOrMoving(imu, init_stamps, poses, config.init, config.imu.gravity, config.use_wheel);
}

// Mode D (init/visual_inertial_poses.h): the IMU's metric poses from the camera's tracks and the IMU over the
// waiting nodes, placed at restart_pose, then the moving alignment on them for the velocities, gravity and
// the gyro bias.
Expected<InertialAlignment> InertialOdometry::Impl::VisualInertialAlignment(std::vector<SE3>& poses) {
  std::vector<ImuPreintegration> preintegrations;
  for (std::size_t k = 1; k < init_stamps.size(); ++k) {
    Expected<ImuPreintegration> pre = imu.Preintegrate(init_stamps[k - 1], init_stamps[k], nullptr);
    if (!pre) return pre.status();
    preintegrations.push_back(std::move(*pre));
  }
  VisualInertialStartConfig start_config;
  start_config.gravity = config.imu.gravity;
  start_config.max_gravity_error = config.init.max_gravity_error;
  start_config.max_tilt_sigma_rad = config.init.max_tilt_sigma_deg * std::numbers::pi / 180;
  Expected<VisualInertialStart> start =
      VisualInertialPoses(preintegrations, visual->Tracks(init_stamps), config.T_body_camera, start_config);
  if (!start) return start.status();
  for (std::size_t k = 0; k < poses.size(); ++k) poses[k] = restart_pose * start->poses[k];
  Expected<InertialAlignment> alignment = LidarAidedAlignment(poses, std::move(preintegrations), config.init);
  if (alignment)
    alignment->mode = start->scale_from_rig ? "visual-inertial (the stereo rig's scale)" : "visual-inertial";
  return alignment;
}

// Poses T_lo_imu of the IMU at `stamps` from the wheel alone (without the wheel: all at restart_pose, which
// only the static alignment accepts): T_lo_imu(t_k+1) = T_lo_imu(t_k) T_body_wheel
// dT_wheel T_body_wheel^-1 (WheelProvider::Motion), starting at restart_pose, carried from restart_stamp to
// the first stamp when the wheel covers that (after an IMU gap: the position continues across it).
Expected<std::vector<SE3>> InertialOdometry::Impl::DeadReckon(const std::vector<Stamp>& stamps) const {
  SE3 pose = restart_pose;
  if (!config.use_wheel) return std::vector<SE3>(stamps.size(), pose);
  if (restart_stamp)
    if (Expected<SE3> across = wheel.Motion(*restart_stamp, stamps.front())) pose = pose * *across;
  std::vector<SE3> poses = {pose};
  for (std::size_t k = 1; k < stamps.size(); ++k) {
    Expected<SE3> motion = wheel.Motion(stamps[k - 1], stamps[k]);
    if (!motion) return Status::Error("wheel dead reckoning: " + motion.status().message());
    poses.push_back(poses.back() * *motion);
  }
  return poses;
}

// The gyro bias prior's sigma: init_gyro_bias_sigma after a static start (the mean rate at rest); after a
// moving one the bias came from the rotations of the wheel's dead reckoning over the init window, whose yaw
// is uncertain by yaw_rate_density sqrt(T) over its span T, so its bias by yaw_rate_density / sqrt(T) (a
// real skid-steer base or a filtered odometry stream gives 0.01-0.02 rad/s there; the window then refines
// it from the wheel's yaw rate).
double InertialOdometry::Impl::GyroBiasPriorSigma(const InertialAlignment& alignment) const {
  if (alignment.mode == "static") return config.init_gyro_bias_sigma;
  const double span_s = ToSeconds(init_stamps.back() - init_stamps.front());
  return std::max(config.init_gyro_bias_sigma, config.wheel.yaw_rate_density / std::sqrt(span_s));
}

// Builds the window from an alignment: the poses rotated into the gravity-aligned world about the first
// one's position (so a restart continues where the last window ended), the velocities and biases of the
// alignment, IMU and wheel factors between consecutive nodes and the gauge prior on the first; then the
// first solve. Fails, leaving no node, when the IMU does not cover an interval.
Status InertialOdometry::Impl::Start(const InertialAlignment& alignment, const std::vector<SE3>& poses) {
  NavState biases;
  biases.accel_bias = alignment.accel_bias;
  biases.gyro_bias = alignment.gyro_bias;
  std::vector<ImuPreintegration> preintegrations;
  for (std::size_t k = 1; k < init_stamps.size(); ++k) {
    Expected<ImuPreintegration> pre =
        imu.Preintegrate(init_stamps[k - 1], init_stamps[k], SpeedBiasBlock(biases).data());
    if (!pre) return pre.status();
    preintegrations.push_back(std::move(*pre));
  }
  const Eigen::Vector3d p0 = poses.front().translation();
  const SE3 T_gravity_lo(alignment.R_gravity_lo, p0 - alignment.R_gravity_lo * p0);
  for (std::size_t k = 0; k < init_stamps.size(); ++k) {
    NavState state = biases;
    state.velocity = alignment.velocities[k];
    WindowNode node;
    node.stamp = init_stamps[k];
    node.pose = PoseBlock(T_gravity_lo * poses[k]);
    node.speed_bias = SpeedBiasBlock(state);
    const long id = PushNode(node);
    if (k == 0) {
      AddGaugePrior();
      graph.Add(FactorKind::kStatePrior, id,
                MakeBiasPriorFactor(alignment.accel_bias, alignment.gyro_bias, config.init_accel_bias_sigma,
                                    GyroBiasPriorSigma(alignment)),
                nullptr, {nodes.front().speed_bias.data()}, /*anchors=*/true);
    } else {
      LinkNode(id, std::move(preintegrations[k - 1]));
    }
  }
  inertial = true;
  init_stamps.clear();
  restart_stamp.reset();
  last_init_failure.clear();
  InertialOdometryStats stats;  // the first solve is not a node's: not in the per-node figures
  SolveAndSlide(stats);
  return {};
}

// Ends the window. keep_window: its nodes are final and become keyframes (the end of the data, an IMU
// gap); otherwise they are dropped (divergence). The next initialization starts at the last node's pose
// (the last keyframe's when that is not finite, else the identity).
void InertialOdometry::Impl::Restart(bool keep_window) {
  if (!nodes.empty()) {
    restart_pose = NodePose(LastNodeId());
    restart_stamp = nodes.back().stamp;
  }
  if (!restart_pose.matrix().allFinite())
    restart_pose = finished.empty() ? SE3() : finished.back().T_world_body;
  if (keep_window)
    while (!nodes.empty()) ReleaseOldest();
  nodes.clear();
  first_node_id = 0;
  imu_scores.clear();
  graph.Clear();
  if (visual) visual->Reset();
  AttachProviders();
  if (gnss) gnss->Reset();
  inertial = false;
  init_stamps.clear();
  last_init_failure.clear();
}

}  // namespace uf::estimator
