// Solving the window and marginalizing its oldest states (see odometry_window.h).
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <unordered_set>

#include "odometry/estimator/lidar_odometry/odometry_window.h"
#include "odometry/estimator/window/marginalization.h"

namespace uf::estimator {

// One solve of the window. The gauge: the marginalization prior when there is one; before the first
// marginalization the oldest scan's begin node is held constant. Its end node stays free: holding it too
// would freeze the first scan's (unknown) sweep motion and make the motion prior fight the data. Returns
// false when the solver fails.
//
// new_scan_only: the ICP rounds of a new scan move only its own nodes (every other node constant, only its
// residuals and the motion factors that touch its nodes): a small problem, cheap to repeat.
bool LidarOdometry::Impl::Solve(int* iterations, bool new_scan_only) {
  const StageTimer timer(new_scan_only ? stats.register_ms : stats.window_ms);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.enable_fast_removal = false;
  ceres::Problem problem(problem_options);
  for (Node& node : nodes) {
    problem.AddParameterBlock(node.pose.data(), kPoseSize, &manifold);
    if (inertial) problem.AddParameterBlock(node.speed_bias.data(), kSpeedBiasSize);
  }
  const bool use_prior = prior && !new_scan_only;
  const long first_free = new_scan_only ? window.back().begin_node
                          : use_prior   ? first_node_id
                                        : window.front().begin_node + 1;
  for (long id = first_node_id; id < first_free; ++id) {
    problem.SetParameterBlockConstant(NodeAt(id).pose.data());
    if (inertial && (new_scan_only || id < window.front().begin_node))
      problem.SetParameterBlockConstant(NodeAt(id).speed_bias.data());
  }
  // Motion factors ending at node id touch a free node iff id >= first_free.
  for (long id = std::max(first_node_id + 1, first_free); id <= LastNodeId(); ++id) {
    Node& node = NodeAt(id);
    if (node.motion_prior && id >= first_node_id + 2)
      problem.AddResidualBlock(node.motion_prior.get(), nullptr, NodeAt(id - 2).pose.data(),
                               NodeAt(id - 1).pose.data(), node.pose.data());
    if (node.imu_factor && inertial)
      problem.AddResidualBlock(node.imu_factor.get(), nullptr, NodeAt(id - 1).pose.data(),
                               NodeAt(id - 1).speed_bias.data(), node.pose.data(), node.speed_bias.data());
  }
  for (ScanState& scan : window) {
    if (new_scan_only && &scan != &window.back()) continue;
    double* begin = NodeAt(scan.begin_node).pose.data();
    double* end = NodeAt(scan.end_node).pose.data();
    for (Residual& r : scan.residuals) {
      if (scan.begin_node == scan.end_node) {
        problem.AddResidualBlock(r.cost.get(), r.loss.get(), begin);
      } else {
        problem.AddResidualBlock(r.cost.get(), r.loss.get(), begin, end);
      }
    }
  }
  if (use_prior) problem.AddResidualBlock(prior.get(), nullptr, prior->prior().ParameterBlocks());
  ceres::Solver::Options options;
  options.linear_solver_type = new_scan_only ? ceres::DENSE_QR                 // one scan's nodes
                                             : ceres::SPARSE_NORMAL_CHOLESKY;  // J^T J block-banded
  options.max_num_iterations = config.max_iterations;
  options.max_solver_time_in_seconds = config.max_solver_time_s;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *iterations += static_cast<int>(summary.iterations.size());
  return summary.termination_type != ceres::FAILURE;
}

// IMU factors whose start state's biases moved far from their linearization point integrate again there.
void LidarOdometry::Impl::Relinearize() {
  if (!inertial) return;
  for (long id = first_node_id + 1; id <= LastNodeId(); ++id) {
    Node& node = NodeAt(id);
    if (!node.imu_factor) continue;
    const NavState from = NodeState(id - 1);
    node.imu_factor->Relinearize(from.accel_bias, from.gyro_bias);
  }
}

// Folds the states before keep_from, and every factor touching them (the leaving scan's point-to-plane
// residuals, the motion factors, the previous prior), into a new prior on the states they connect to.
void LidarOdometry::Impl::MarginalizeScan(const ScanState& leaving, long keep_from) {
  const StageTimer timer(stats.marginalize_ms);
  // Motion factors alone say nothing about where the kept states are: without point-to-plane residuals or
  // a previous prior there is nothing to keep (the first scan, registered against nothing, is such a case).
  if (keep_from <= first_node_id || (leaving.residuals.empty() && !prior)) return;
  Marginalizer marginalizer(config.marginalization);
  std::unordered_set<const double*> touched;  // blocks of the factors that go into the prior
  auto leaves = [&](const std::vector<double*>& blocks) {
    bool any = false;
    for (double* block : blocks) {
      for (long id = first_node_id; id < keep_from; ++id)
        any |= block == NodeAt(id).pose.data() || block == NodeAt(id).speed_bias.data();
    }
    if (any) touched.insert(blocks.begin(), blocks.end());
    return any;
  };
  auto add = [&](const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                 std::vector<double*> blocks) {
    if (leaves(blocks)) marginalizer.AddResidualBlock(cost, loss, std::move(blocks));
  };
  for (Node& node : nodes) marginalizer.SetPoseBlock(node.pose.data());
  for (const Residual& r : leaving.residuals) {
    if (leaving.begin_node == leaving.end_node) {
      add(r.cost.get(), r.loss.get(), {NodeAt(leaving.begin_node).pose.data()});
    } else {
      add(r.cost.get(), r.loss.get(),
          {NodeAt(leaving.begin_node).pose.data(), NodeAt(leaving.end_node).pose.data()});
    }
  }
  for (long id = first_node_id + 1; id <= LastNodeId() && id <= keep_from + 1; ++id) {
    Node& node = NodeAt(id);
    if (node.motion_prior && id >= first_node_id + 2)
      add(node.motion_prior.get(), nullptr,
          {NodeAt(id - 2).pose.data(), NodeAt(id - 1).pose.data(), node.pose.data()});
    if (node.imu_factor && inertial)
      add(node.imu_factor.get(), nullptr,
          {NodeAt(id - 1).pose.data(), NodeAt(id - 1).speed_bias.data(), node.pose.data(),
           node.speed_bias.data()});
  }
  if (prior && leaves(prior->prior().ParameterBlocks())) marginalizer.AddPrior(prior.get());
  for (long id = first_node_id; id < keep_from; ++id) {
    Node& node = NodeAt(id);
    if (touched.count(node.pose.data())) marginalizer.MarginalizeBlock(node.pose.data());
    if (touched.count(node.speed_bias.data())) marginalizer.MarginalizeBlock(node.speed_bias.data());
  }
  Expected<std::shared_ptr<MarginalizationPrior>> computed = marginalizer.Compute();
  if (!computed) {
    // Without a prior the window falls back to holding its oldest pose constant: less information, no harm.
    warnings.push_back("marginalization at " + StampText(leaving.stamp) +
                       " failed, prior dropped: " + computed.status().message());
    prior.reset();
    return;
  }
  prior = std::make_unique<MarginalizationFactor>(*computed);
}

}  // namespace uf::estimator
