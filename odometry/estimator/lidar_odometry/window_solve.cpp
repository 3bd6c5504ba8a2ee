// Solving the window and marginalizing its oldest states (see odometry_window.h): which blocks move and
// which factors take part; the graph (window/factor_graph.h) does the rest.
#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {

// One solve of the window. The gauge: the marginalization prior when there is one; before the first
// marginalization the oldest scan's begin node is held constant. Its end node stays free: holding it too
// would freeze the first scan's (unknown) sweep motion and make the motion prior fight the data. Returns
// false when the solver fails.
//
// new_scan_only: the ICP rounds of a new scan move only its own nodes (every other node constant, only its
// point-to-plane factors and the motion factors that touch its nodes): a small problem (12 dof in LO, 30 in
// LIO). Both it and the window (<= 15 x 2 window_size dof) go to the dense Levenberg-Marquardt of
// window/dense_least_squares.h, which has no per-solve setup cost.
bool LidarOdometry::Impl::Solve(int* iterations, bool new_scan_only) {
  const StageTimer timer(new_scan_only ? stats.register_ms : stats.window_ms);
  WindowSolveRequest request;
  request.use_prior = graph.prior() && !new_scan_only;
  const long first_free = new_scan_only       ? window.back().begin_node
                          : request.use_prior ? first_node_id
                                              : window.front().begin_node + 1;
  for (long id = first_node_id; id <= LastNodeId(); ++id) {
    Node& node = NodeAt(id);
    if (id >= first_free) request.free.push_back(node.pose.data());
    // Without a prior the oldest state's speed and biases stay free: only its pose fixes the gauge.
    if (inertial && (id >= first_free || (!new_scan_only && id >= window.front().begin_node)))
      request.free.push_back(node.speed_bias.data());
  }
  if (wheel && wheel->scale_free() && !new_scan_only) request.free.push_back(wheel->scale_block());
  if (gnss && gnss->aligned() && !new_scan_only) request.free.push_back(gnss->alignment_block());
  if (new_scan_only) {
    const long scan = window.back().id;
    request.use = [scan](const Factor& f) { return f.kind != FactorKind::kLidar || f.tag == scan; };
  }
  request.max_iterations = config.max_iterations;
  request.max_time_s = config.max_solver_time_s;
  const WindowSolveResult result = graph.Solve(request);
  *iterations += result.iterations;
  return result.usable;
}

// IMU factors whose start state's biases moved far from their linearization point integrate again there.
void LidarOdometry::Impl::Relinearize() {
  if (!inertial) return;
  for (Factor& factor : graph.Entries(FactorKind::kImu)) {
    const NavState from = NodeState(factor.tag - 1);
    static_cast<ImuFactor*>(factor.cost.get())->Relinearize(from.accel_bias, from.gyro_bias);
  }
}

// Folds the nodes before keep_from, and every factor touching them, into the prior (or just drops them when
// marginalization is off); `stamp` names the leaving scan in a warning.
void LidarOdometry::Impl::MarginalizeBefore(long keep_from, Stamp stamp) {
  const StageTimer timer(stats.marginalize_ms);
  std::vector<double*> leaving;
  for (long id = first_node_id; id < keep_from && id <= LastNodeId(); ++id) {
    leaving.push_back(NodeAt(id).pose.data());
    leaving.push_back(NodeAt(id).speed_bias.data());
  }
  if (!config.marginalize || keep_from > LastNodeId()) {
    graph.RemoveBlocks(leaving);
    return;
  }
  // Without a prior the window falls back to holding its oldest pose constant: less information, no harm.
  if (Status s = graph.Marginalize(leaving, config.marginalization); !s.ok())
    warnings.push_back("marginalization at " + StampText(stamp) + " failed, prior dropped: " + s.message());
}

}  // namespace uf::estimator
