// Solving the window and marginalizing its oldest states (see odometry_window.h).
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <unordered_set>

#include "odometry/estimator/lidar_odometry/odometry_window.h"
#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/estimator/window/marginalization.h"

namespace uf::estimator {

// The blocks and residuals of one solve, handed to a solver-specific sink: pose(block, constant),
// speed_bias(block, constant), residual(cost, loss, blocks). See Impl::Solve for the gauge and the
// new_scan_only variant.
template <typename PoseSink, typename SpeedBiasSink, typename ResidualSink>
void LidarOdometry::Impl::EnumerateProblem(bool new_scan_only, PoseSink&& pose, SpeedBiasSink&& speed_bias,
                                           ResidualSink&& residual) {
  Impl& w = *this;
  const bool use_prior = w.prior && !new_scan_only;
  const long first_free = new_scan_only ? w.window.back().begin_node
                          : use_prior   ? w.first_node_id
                                        : w.window.front().begin_node + 1;
  for (long id = w.first_node_id; id <= w.LastNodeId(); ++id) {
    Node& node = w.NodeAt(id);
    pose(node.pose.data(), id < first_free);
    if (w.inertial)
      speed_bias(node.speed_bias.data(),
                 id < first_free && (new_scan_only || id < w.window.front().begin_node));
  }
  // Motion factors ending at node id touch a free node iff id >= first_free.
  for (long id = std::max(w.first_node_id + 1, first_free); id <= w.LastNodeId(); ++id) {
    Node& node = w.NodeAt(id);
    if (node.motion_prior && id >= w.first_node_id + 2)
      residual(node.motion_prior.get(), nullptr,
               {w.NodeAt(id - 2).pose.data(), w.NodeAt(id - 1).pose.data(), node.pose.data()});
    if (node.imu_factor && w.inertial)
      residual(node.imu_factor.get(), nullptr,
               {w.NodeAt(id - 1).pose.data(), w.NodeAt(id - 1).speed_bias.data(), node.pose.data(),
                node.speed_bias.data()});
  }
  for (ScanState& scan : w.window) {
    if (new_scan_only && &scan != &w.window.back()) continue;
    double* begin = w.NodeAt(scan.begin_node).pose.data();
    double* end = w.NodeAt(scan.end_node).pose.data();
    for (Residual& r : scan.residuals) {
      if (scan.begin_node == scan.end_node) {
        residual(r.cost.get(), r.loss.get(), {begin});
      } else {
        residual(r.cost.get(), r.loss.get(), {begin, end});
      }
    }
  }
  if (use_prior) residual(w.prior.get(), nullptr, w.prior->prior().ParameterBlocks());
}

// One solve of the window. The gauge: the marginalization prior when there is one; before the first
// marginalization the oldest scan's begin node is held constant. Its end node stays free: holding it too
// would freeze the first scan's (unknown) sweep motion and make the motion prior fight the data. Returns
// false when the solver fails.
//
// new_scan_only: the ICP rounds of a new scan move only its own nodes (every other node constant, only its
// residuals and the motion factors that touch its nodes): a small problem (12 dof in LO, 30 in LIO), solved
// by the dense Levenberg-Marquardt of window/dense_least_squares.h, which has no per-solve setup cost. The
// LO window (poses only, <= 6 x 2 window_size dof) is solved by it as well; LIO's window (speed and biases
// too) goes to Ceres with a sparse Cholesky.
bool LidarOdometry::Impl::Solve(int* iterations, bool new_scan_only) {
  const StageTimer timer(new_scan_only ? stats.register_ms : stats.window_ms);
  if (new_scan_only || !inertial) {
    DenseLeastSquares problem;
    EnumerateProblem(
        new_scan_only,
        [&](double* block, bool constant) {
          if (!constant) problem.AddPoseBlock(block);
        },
        [&](double* block, bool constant) {
          if (!constant) problem.AddEuclideanBlock(block, kSpeedBiasSize);
        },
        [&](const ceres::CostFunction* cost, const ceres::LossFunction* loss,
            const std::vector<double*>& blocks) { problem.AddResidualBlock(cost, loss, blocks); });
    DenseSolverOptions options;
    options.max_iterations = config.max_iterations;
    options.max_time_s = config.max_solver_time_s;
    const DenseSolverSummary summary = problem.Solve(options);
    *iterations += summary.iterations;
    return summary.usable;
  }
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.enable_fast_removal = false;
  ceres::Problem problem(problem_options);
  EnumerateProblem(
      new_scan_only,
      [&](double* block, bool constant) {
        problem.AddParameterBlock(block, kPoseSize, &manifold);
        if (constant) problem.SetParameterBlockConstant(block);
      },
      [&](double* block, bool constant) {
        problem.AddParameterBlock(block, kSpeedBiasSize);
        if (constant) problem.SetParameterBlockConstant(block);
      },
      [&](const ceres::CostFunction* cost, const ceres::LossFunction* loss,
          const std::vector<double*>& blocks) {
        problem.AddResidualBlock(const_cast<ceres::CostFunction*>(cost),
                                 const_cast<ceres::LossFunction*>(loss), blocks);
      });
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;  // J^T J block-banded
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
