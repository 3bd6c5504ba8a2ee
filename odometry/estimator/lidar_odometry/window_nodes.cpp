// The nodes of the window: their initial guesses, the IMU between them and the inertial initialization
// (see odometry_window.h).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/estimator/factors/sweep_velocity_factor.h"
#include "odometry/estimator/lidar_odometry/imu_sweep_correction.h"
#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {

// Constant-velocity extrapolation from node id to `stamp` (restart_pose before any node), with the twist
// between node id and the latest node at least `baseline` before it (else the oldest), over at most
// max_prediction_s (after a longer gap the pose holds there: a velocity seen seconds ago says little):
// xi = Log(T_base^-1 T_id) / (t_id - t_base),  T(stamp) = T_id Exp(xi min(stamp - t_id, max_prediction_s)).
// Baseline 0 takes the last node pair (a sweep's begin and end node): the current twist, but resting on the
// deskew alone and noisy; a longer one averages, and lags where the motion changes.
SE3 LidarOdometry::Impl::ExtrapolateFrom(long id, Stamp stamp, Stamp baseline) {
  if (nodes.empty()) return restart_pose;
  const SE3 T_last = NodePose(id);
  if (id <= first_node_id) return T_last;
  long base = id - 1;
  while (base > first_node_id && NodeAt(id).stamp - NodeAt(base).stamp < baseline) --base;
  const double dt = ToSeconds(NodeAt(id).stamp - NodeAt(base).stamp);
  const Vector6d xi = (NodePose(base).inverse() * T_last).Log() / dt;
  return T_last * SE3::Exp(xi * std::min(ToSeconds(stamp - NodeAt(id).stamp), config.max_prediction_s));
}

// A new node at `stamp`. Initialized LIO: the IMU prediction from the last node and an IMU factor to it.
// Otherwise (LO, LIO before initialization, or an IMU gap): the constant-velocity extrapolation and prior.
long LidarOdometry::Impl::AddNode(Stamp stamp) {
  Node node;
  node.stamp = stamp;
  std::unique_ptr<ImuFactor> imu_factor;
  if (inertial && !nodes.empty()) {
    node.speed_bias = nodes.back().speed_bias;
    Expected<ImuPreintegration> pre =
        imu.Preintegrate(nodes.back().stamp, stamp, nodes.back().speed_bias.data());
    if (pre) {
      NavState predicted = pre->Predict(NodeState(LastNodeId()));
      node.pose = PoseBlock(predicted.T_world_imu);
      node.speed_bias = SpeedBiasBlock(predicted);
      imu_factor = std::make_unique<ImuFactor>(std::move(*pre));
    } else {
      warnings.push_back("IMU at " + StampText(stamp) + ": " + pre.status().message() +
                         "; bridged with the constant-velocity prior");
    }
  }
  const WheelReference reference = WheelReferenceOf(imu_factor ? &imu_factor->preintegration() : nullptr);
  if (!imu_factor) node.pose = PoseBlock(Extrapolate(stamp));
  nodes.push_back(node);
  const long id = LastNodeId();
  graph.AddPoseBlock(NodeAt(id).pose.data());
  graph.AddEuclideanBlock(NodeAt(id).speed_bias.data(), kSpeedBiasSize);
  if (imu_factor) {
    AddImuFactor(id, std::move(imu_factor));
  } else if (nodes.size() >= 3) {
    AddMotionPrior(id);
  }
  if (wheel && nodes.size() >= 2) LinkWheel(id, reference);
  return id;
}

// The wheel factor between nodes id - 1 and id; without wheel samples over the interval the nodes go on
// without it (a warning). reference: whether node id holds the IMU's prediction, which the wheel's
// scheduling scores it against (WheelReference).
void LidarOdometry::Impl::LinkWheel(long id, WheelReference reference) {
  if (Status s = wheel->Link(graph, id, NodeAt(id - 1).pose.data(), NodeAt(id).pose.data(),
                             NodeAt(id - 1).stamp, NodeAt(id).stamp, reference,
                             NodeAt(id - 1).speed_bias.data(), NodeAt(id).speed_bias.data());
      !s.ok())
    warnings.push_back("wheel factor at " + StampText(NodeAt(id).stamp) + " skipped: " + s.message());
  // Once initialized (the velocities are states then), the stationary branch holds intervals at rest.
  if (inertial)
    wheel->LinkAtRest(graph, id, NodeAt(id - 1).pose.data(), NodeAt(id).pose.data(),
                      NodeAt(id - 1).speed_bias.data(), NodeAt(id).speed_bias.data(), NodeAt(id - 1).stamp,
                      NodeAt(id).stamp);
}

Status LidarOdometry::Impl::AddWheel(const WheelSample& sample) {
  if (std::optional<std::string> skipped = wheel->Add(sample)) warnings.push_back(*skipped);
  ProcessReady(/*flush=*/false);
  return {};
}

// The GNSS fixes the nodes cover join the window (providers/gnss_provider.h); only once LIO is initialized:
// the alignment is yaw and translation, so the world must be gravity-aligned.
void LidarOdometry::Impl::LinkGnss() {
  if (!gnss || !inertial) return;
  gnss->Link(graph, NodeViews(nodes), warnings);
}

void LidarOdometry::Impl::CorrectSweepByImu(ScanState& scan) {
  const Stamp begin = NodeAt(scan.begin_node).stamp, end = NodeAt(scan.end_node).stamp;
  const NavState begin_state = NodeState(scan.begin_node);
  std::vector<SE3> predicted{begin_state.T_world_imu};
  for (int i = 1; i <= ImuSweepCorrection::kSteps; ++i) {
    const Stamp t = begin + (end - begin) * i / ImuSweepCorrection::kSteps;
    Expected<ImuPreintegration> pre = imu.Preintegrate(begin, t, NodeAt(scan.begin_node).speed_bias.data());
    if (!pre) return;  // a gap: the nodes' interpolation alone
    predicted.push_back(pre->Predict(begin_state).T_world_imu);
  }
  const ImuSweepCorrection correction(predicted, config.T_body_lidar);
  for (std::vector<PreparedPoint>* points : {&scan.points, &scan.map_points, &scan.registration_points})
    for (PreparedPoint& p : *points) p.point_lidar = correction.Apply(p.point_lidar, p.alpha);
}

void LidarOdometry::Impl::AddImuFactor(long id, std::unique_ptr<ImuFactor> factor) {
  graph.Add(FactorKind::kImu, id, std::move(factor), nullptr,
            {NodeAt(id - 1).pose.data(), NodeAt(id - 1).speed_bias.data(), NodeAt(id).pose.data(),
             NodeAt(id).speed_bias.data()});
}

// The constant-velocity prior on (id - 2, id - 1, id), its segments divided by their own durations.
void LidarOdometry::Impl::AddMotionPrior(long id) {
  const double dt_ab = ToSeconds(NodeAt(id - 1).stamp - NodeAt(id - 2).stamp);
  const double dt_bc = ToSeconds(NodeAt(id).stamp - NodeAt(id - 1).stamp);
  graph.Add(FactorKind::kMotionPrior, id, MakeConstantVelocityFactor(dt_ab, dt_bc, config.motion), nullptr,
            {NodeAt(id - 2).pose.data(), NodeAt(id - 1).pose.data(), NodeAt(id).pose.data()});
}

// The sweep-velocity prior (factors/sweep_velocity_factor.h) on a scan with nodes of its own, against the
// velocity between the end nodes of the two scans before it (when there are two, with distinct end nodes).
void LidarOdometry::Impl::AddSweepVelocityPrior(const ScanState& scan) {
  const double density = config.motion.sweep_acc_density;
  if (density <= 0 || window.size() < 2) return;
  const long a = window[window.size() - 2].end_node, b = window.back().end_node;
  if (a >= b || a < first_node_id) return;
  const Stamp t_a = NodeAt(a).stamp, t_b = NodeAt(b).stamp;
  const Stamp t_begin = NodeAt(scan.begin_node).stamp, t_end = NodeAt(scan.end_node).stamp;
  SweepVelocityTiming timing;
  timing.dt_reference = ToSeconds(t_b - t_a);
  timing.dt_sweep = ToSeconds(t_end - t_begin);
  timing.dt_mid = ToSeconds((t_begin + t_end) / 2 - (t_a + t_b) / 2);
  if (timing.dt_reference <= 0 || timing.dt_sweep <= 0 || timing.dt_mid <= 0) return;
  graph.Add(FactorKind::kMotionPrior, scan.end_node, MakeSweepVelocityFactor(timing, density), nullptr,
            {NodeAt(a).pose.data(), NodeAt(b).pose.data(), NodeAt(scan.begin_node).pose.data(),
             NodeAt(scan.end_node).pose.data()});
}

Status LidarOdometry::Impl::AddImu(const ImuSample& sample) {
  if (std::optional<std::string> skipped = imu.Add(sample)) {
    warnings.push_back(*skipped);
    return {};
  }
  ProcessReady(/*flush=*/false);
  return {};
}

// Drops IMU (and wheel) samples no node interval needs any more (keeps one before the oldest node).
void LidarOdometry::Impl::TrimStreams() {
  if (nodes.empty()) return;
  if (wheel) wheel->Trim(nodes.front().stamp);
  if (visual) visual->Trim(nodes.front().stamp);
  imu.Trim(nodes.front().stamp);
}

// LIO before initialization: one attempt of the observability-aware initialization per scan
// (init/inertial_initializer.h, fed by window_init.cpp). The latency counts from the first IMU sample, after
// a re-initialization from the new window's first node.
void LidarOdometry::Impl::TryInitializeInertial() {
  if (inertial || nodes.empty()) return;
  if (!initializer.started() || initializer.record().admitted) initializer.Start(InitializationStart());
  InertialInitializer::Outcome outcome = initializer.Attempt(imu, InitializationWindow());
  if (outcome.warning) warnings.push_back(*outcome.warning);
  if (outcome.verdict != AdmissionCheck::Verdict::kAdmitted) return;
  ApplyInertialAlignment(outcome.alignment);
  init_summary = initializer.record().Summary();
}

// Rotates the window into the gravity-aligned world, gives its nodes velocities and biases, replaces the
// constant-velocity priors by IMU factors and rebuilds the map and the associations in the new frame. The
// rotation turns about the first node's position, so a re-initialization continues where the last one ended.
// The alignment covers the newest alignment.velocities.size() nodes; older ones (before a rejected
// initialization window) keep their constant-velocity priors and get the LO velocity between their poses.
void LidarOdometry::Impl::ApplyInertialAlignment(const InertialAlignment& alignment) {
  const Eigen::Vector3d p0 = NodePose(first_node_id).translation();
  const SE3 T_gravity_lo(alignment.R_gravity_lo, p0 - alignment.R_gravity_lo * p0);
  const long first_aligned = LastNodeId() + 1 - static_cast<long>(alignment.velocities.size());
  inertial = true;
  for (long id = first_node_id; id <= LastNodeId(); ++id)
    NodeAt(id).pose = PoseBlock(T_gravity_lo * NodePose(id));
  ReleaseHeld(T_gravity_lo);  // the keyframes that left the window before, in the same world
  gravity_reference = GravityReference{NodePose(LastNodeId()).so3(), config.T_body_lidar.so3()};
  SetWorldGravity();  // along -z: the world is aligned with gravity now
  for (long id = first_node_id; id <= LastNodeId(); ++id) {
    Node& node = NodeAt(id);
    NavState state;
    if (id >= first_aligned) {
      state.velocity = alignment.velocities[static_cast<std::size_t>(id - first_aligned)];
    } else {
      const long next = id + 1;  // <= first_aligned <= LastNodeId()
      state.velocity = (NodePose(next).translation() - NodePose(id).translation()) /
                       ToSeconds(NodeAt(next).stamp - node.stamp);
    }
    state.accel_bias = alignment.accel_bias;
    state.gyro_bias = alignment.gyro_bias;
    node.speed_bias = SpeedBiasBlock(state);
    if (id <= first_aligned) continue;
    Expected<ImuPreintegration> pre =
        imu.Preintegrate(NodeAt(id - 1).stamp, node.stamp, node.speed_bias.data());
    if (!pre) continue;  // keeps its constant-velocity prior
    graph.Remove(FactorKind::kMotionPrior, id);
    AddImuFactor(id, std::make_unique<ImuFactor>(std::move(*pre)));
  }
  graph.DropPrior();  // a prior from before would live in the old frame
  RebuildMap();
}

// Re-initialization: the window, the prior and the map start over (the next scan is a first scan), at the
// last node's pose.
void LidarOdometry::Impl::Reset() {
  restart_pose = nodes.empty() ? restart_pose : NodePose(LastNodeId());
  if (!restart_pose.matrix().allFinite()) restart_pose = SE3();
  nodes.clear();
  window.clear();
  first_node_id = 0;
  graph.Clear();
  if (visual) visual->Reset();
  AttachProviders();
  if (gnss) gnss->Reset();
  map.Clear();
  inertial = false;
  gravity_reference.reset();
  SetWorldGravity();
  last_registered.reset();
  last_move_m = 0;
  recent_match_fractions.clear();
  recent_guess_turns.clear();
  consecutive_rejections = 0;
}

}  // namespace uf::estimator
