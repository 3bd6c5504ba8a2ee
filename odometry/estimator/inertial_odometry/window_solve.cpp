// The nodes of the wheel-inertial window, their factors, the solve and the marginalization (see
// inertial_window.h); the graph (window/factor_graph.h) does the rest.
#include <chrono>

#include "odometry/estimator/factors/gauge_prior_factor.h"
#include "odometry/estimator/factors/imu_factor.h"
#include "odometry/estimator/inertial_odometry/inertial_window.h"
#include "odometry/estimator/providers/imu_reliability.h"

namespace uf::estimator {
namespace {

// How firmly the gauge prior holds the first node's position and yaw. The prior only picks a point of the
// cost's null space (gauge_prior_factor.h), so these set the conditioning, not the solution: information
// 1e6 per direction, between the IMU factor's on a 0.1 s interval (~1e8 on the position) and the loose
// non-holonomic terms, and far above the marginalization's eigenvalue threshold.
constexpr double kGaugeSigmaPosition = 1e-3;  // m
constexpr double kGaugeSigmaYaw = 1e-3;       // rad

}  // namespace

long InertialOdometry::Impl::PushNode(const WindowNode& node) {
  nodes.push_back(node);
  graph.AddPoseBlock(nodes.back().pose.data());
  graph.AddEuclideanBlock(nodes.back().speed_bias.data(), kSpeedBiasSize);
  if (visual) visual->Observe(LastNodeId(), node.stamp);
  return LastNodeId();
}

// The factors between node id - 1 and node id: the IMU's, and the wheel's when the wheel samples cover the
// interval (else a warning, and the IMU alone bridges it), and the stationary branch's where the wheels
// stand. Another provider links its factors here.
void InertialOdometry::Impl::LinkNode(long id, ImuPreintegration imu_preintegration) {
  WindowNode &from = NodeAt(id - 1), &to = NodeAt(id);
  const WheelReference reference = WheelReferenceOf(&imu_preintegration);
  graph.Add(FactorKind::kImu, id, std::make_unique<ImuFactor>(std::move(imu_preintegration)), nullptr,
            {from.pose.data(), from.speed_bias.data(), to.pose.data(), to.speed_bias.data()});
  if (!config.use_wheel) return;
  // The new node holds the IMU's prediction: the wheel's interval is scored against it (scheduling), unless
  // the IMU clipped there (it saw less than happened).
  if (Status s = wheel.Link(graph, id, from.pose.data(), to.pose.data(), from.stamp, to.stamp, reference,
                            from.speed_bias.data(), to.speed_bias.data());
      !s.ok())
    warnings.push_back("wheel factor at " + StampText(to.stamp) + " skipped: " + s.message());
  wheel.LinkAtRest(graph, id, from.pose.data(), to.pose.data(), from.speed_bias.data(), to.speed_bias.data(),
                   from.stamp, to.stamp);
}

// The gauge of the window (gauge_prior_factor.h): the oldest node's position and yaw, anchoring, so the
// marginalization folds it into the prior when the node leaves.
void InertialOdometry::Impl::AddGaugePrior() {
  graph.Add(FactorKind::kStatePrior, first_node_id,
            MakeGaugePriorFactor(NodePose(first_node_id), kGaugeSigmaPosition, kGaugeSigmaYaw), nullptr,
            {nodes.front().pose.data()}, /*anchors=*/true);
}

// One dense Levenberg-Marquardt solve of every node, the wheel scale and (with the camera) the landmarks'
// inverse depths and t_d. The IMU factors whose start node's biases moved beyond the first-order range
// integrate again at them first; the camera's new landmarks and observations are linked first and its
// outliers dropped after.
bool InertialOdometry::Impl::Solve(int* iterations, int* outliers) {
  for (Factor& factor : graph.Entries(FactorKind::kImu)) {
    const NavState from = NodeNavState(NodeAt(factor.tag - 1));
    static_cast<ImuFactor*>(factor.cost.get())->Relinearize(from.accel_bias, from.gyro_bias);
  }
  if (gnss && inertial) gnss->Link(graph, NodeViews(nodes), warnings);
  const PoseBlockOf pose_of = [this](long id) { return NodeAt(id).pose.data(); };
  if (visual) visual->Link(graph, pose_of);
  WindowSolveRequest request;
  for (const NodeView& node : NodeViews(nodes)) {
    request.free.push_back(node.pose);
    request.free.push_back(node.speed_bias);
  }
  if (config.use_wheel && wheel.scale_free()) request.free.push_back(wheel.scale_block());
  if (visual) visual->AppendFreeBlocks(request.free);
  if (gnss)
    for (double* block : gnss->StateBlocks()) request.free.push_back(block);
  request.use_prior = graph.prior() != nullptr;
  request.solver = WindowSolver::kDense;
  request.max_iterations = visual ? config.visual.max_iterations : config.max_iterations;
  request.max_time_s = visual ? config.visual.max_solver_time_s : config.max_solver_time_s;
  const WindowSolveResult result = graph.Solve(request);
  *iterations += result.iterations;
  if (visual && result.usable) *outliers += visual->DropOutliers(graph);
  return result.usable;
}

// The oldest node leaves: its factors (and the gauge prior or the previous prior), and with the camera the
// landmarks anchored in it, fold into the marginalization prior, or are dropped with marginalize off; it
// becomes a keyframe. Without a prior afterwards (marginalize off, or a failed marginalization) the new
// oldest node takes the gauge prior.
void InertialOdometry::Impl::MarginalizeOldest(double* ms) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double*> leaving = {nodes.front().pose.data(), nodes.front().speed_bias.data()};
  // The IMU factor leaving with the node is scored at its last estimate, for the next node's keyframe.
  if (std::optional<ImuReliability> score = ScoreImuFactor(graph, first_node_id + 1))
    imu_scores[first_node_id + 1] = *score;
  if (visual)
    for (double* inverse_depth : visual->AnchoredBlocks(first_node_id)) leaving.push_back(inverse_depth);
  const Stamp leaving_stamp = nodes.front().stamp;
  if (gnss)
    for (double* offset : gnss->OffsetBlocksUpTo(leaving_stamp)) leaving.push_back(offset);
  if (!config.marginalize) {
    graph.RemoveBlocks(leaving);
  } else if (Status s = graph.Marginalize(leaving, config.marginalization); !s.ok()) {
    warnings.push_back("marginalization at " + StampText(nodes.front().stamp) +
                       " failed, prior dropped: " + s.message());
  }
  if (visual) visual->ForgetNode(first_node_id);
  if (gnss) gnss->DropOffsetsUpTo(leaving_stamp);
  ReleaseOldest();
  if (!graph.prior()) AddGaugePrior();
  TrimStreams();
  *ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The IMU score of the interval ending at node `id`: kept when its factor left the window, else (the end of
// the data, a restart) read off the factor still in it. Earlier ids are dropped.
std::optional<ImuReliability> InertialOdometry::Impl::TakeImuScore(long id) {
  std::optional<ImuReliability> score;
  if (auto it = imu_scores.find(id); it != imu_scores.end()) score = it->second;
  imu_scores.erase(imu_scores.begin(), imu_scores.upper_bound(id));
  return score ? score : ScoreImuFactor(graph, id);
}

// The oldest node as a keyframe (body = IMU), out of the window. Its blocks must no longer be in use by the
// graph (marginalized, removed, or the graph about to be cleared).
void InertialOdometry::Impl::ReleaseOldest() {
  const NavState state = NodeNavState(nodes.front());
  Keyframe keyframe;
  keyframe.stamp = state.stamp;
  keyframe.T_world_body = state.T_world_imu;
  keyframe.velocity = state.velocity;
  keyframe.bias_acc = state.accel_bias;
  keyframe.bias_gyro = state.gyro_bias;
  keyframe.inertial = true;
  keyframe.imu_reliability = TakeImuScore(first_node_id);
  if (config.use_wheel) keyframe.wheel_consistency = wheel.TakeConsistency(first_node_id);
  if (gnss) keyframe.gnss_checks = gnss->TakeChecks(state.stamp);
  if (visual) keyframe.camera_checks = visual->TakeChecks(state.stamp);
  finished.push_back(std::move(keyframe));
  nodes.pop_front();
  ++first_node_id;
}

}  // namespace uf::estimator
