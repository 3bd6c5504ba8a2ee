#include "odometry/estimator/lidar_odometry/lidar_odometry.h"

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Geometry>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <deque>
#include <string>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/estimator/lidar_odometry/scan_preparation.h"
#include "odometry/estimator/lidar_odometry/sweep_poses.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

using PoseArray = std::array<double, kPoseSize>;
constexpr Stamp kSharedNodeTolerance = 1'000'000;  // 1 ms: a scan starting this close to the last end
                                                   // shares that node
constexpr double kConvergedTranslation = 0.005;    // m, registration converged when a round moves less
constexpr double kConvergedRotation = 0.001;       // rad

struct Node {
  Stamp stamp = 0;
  PoseArray pose{};
  // Constant-velocity prior on (previous-previous, previous, this) node; null for the first two nodes.
  std::unique_ptr<ceres::CostFunction> motion_prior;
};

struct Residual {
  std::unique_ptr<ceres::CostFunction> cost;
  std::unique_ptr<ceres::LossFunction> loss;
};

struct ScanState {
  Stamp stamp = 0, end = 0;
  long begin_node = 0, end_node = 0;  // node ids (equal for a scan without duration)
  std::vector<PreparedPoint> points;  // all prepared points, for the keyframe's deskewed scan
  std::vector<PreparedPoint> registration_points;
  std::vector<Residual> residuals;  // of the last association
};

std::string StampText(Stamp stamp) { return std::to_string(ToSeconds(stamp)) + " s"; }

}  // namespace

struct LidarOdometry::Impl {
  explicit Impl(const LidarOdometryConfig& c) : config(c), map(c.map) {}

  LidarOdometryConfig config;
  VoxelHashMap map;
  PoseManifold manifold;
  std::deque<Node> nodes;  // ids first_node_id ...
  long first_node_id = 0;
  std::deque<ScanState> window;
  std::vector<Keyframe> finished;
  std::vector<std::string> warnings;
  OdometryStats stats;
  bool has_last = false;
  Stamp last_stamp = 0, last_end = 0;

  Node& NodeAt(long id) { return nodes[static_cast<std::size_t>(id - first_node_id)]; }
  long LastNodeId() const { return first_node_id + static_cast<long>(nodes.size()) - 1; }
  SE3 NodePose(long id) { return PoseFromBlock(NodeAt(id).pose.data()); }

  // Constant-velocity extrapolation from the last two nodes to `stamp` (identity before any node):
  // xi = Log(T_{n-1}^-1 T_n) / (t_n - t_{n-1}),  T(stamp) = T_n Exp(xi (stamp - t_n)).
  SE3 Extrapolate(Stamp stamp) {
    if (nodes.empty()) return SE3();
    const long last = LastNodeId();
    const SE3 T_last = NodePose(last);
    if (nodes.size() < 2) return T_last;
    const Node& previous = NodeAt(last - 1);
    const double dt = ToSeconds(NodeAt(last).stamp - previous.stamp);
    const Vector6d xi = (PoseFromBlock(previous.pose.data()).inverse() * T_last).Log() / dt;
    return T_last * SE3::Exp(xi * ToSeconds(stamp - NodeAt(last).stamp));
  }

  long AddNode(Stamp stamp) {
    Node node;
    node.stamp = stamp;
    node.pose = PoseBlock(Extrapolate(stamp));
    if (nodes.size() >= 2) {
      const double dt_ab = ToSeconds(nodes[nodes.size() - 1].stamp - nodes[nodes.size() - 2].stamp);
      const double dt_bc = ToSeconds(stamp - nodes.back().stamp);
      node.motion_prior = MakeConstantVelocityFactor(dt_ab, dt_bc, config.motion);
    }
    nodes.push_back(std::move(node));
    return LastNodeId();
  }

  SweepPoses Sweep(const ScanState& scan) {
    return SweepPoses(NodePose(scan.begin_node), NodePose(scan.end_node), config.T_body_lidar,
                      scan.begin_node == scan.end_node);
  }

  // Point-to-plane residuals of `scan` against the map at the current node poses: up to
  // max_residuals_per_scan points with a plane, visited at an even stride (then the offsets in between) so
  // that they spread over the whole scan.
  void Associate(ScanState& scan) {
    scan.residuals.clear();
    const auto& points = scan.registration_points;
    const std::size_t n = points.size(), cap = static_cast<std::size_t>(config.max_residuals_per_scan);
    const std::size_t step = std::max<std::size_t>(1, n / cap);
    const bool single = scan.begin_node == scan.end_node;
    const SweepPoses sweep = Sweep(scan);
    for (std::size_t offset = 0; offset < step && scan.residuals.size() < cap; ++offset) {
      for (std::size_t i = offset; i < n && scan.residuals.size() < cap; i += step) {
        const PreparedPoint& p = points[i];
        const Eigen::Vector3d p_world = sweep.At(p.alpha) * p.point_lidar;
        const std::optional<Plane> plane = map.PlaneNear(p_world);
        // Correspondence gate: a plane farther than max_plane_distance_m from the point is another surface.
        if (!plane || std::abs(plane->normal.dot(p_world - plane->point)) > config.max_plane_distance_m)
          continue;
        Residual r;
        if (single) {
          r.cost =
              std::make_unique<PointToPlaneFactorSinglePose>(config.T_body_lidar * p.point_lidar, *plane);
        } else {
          r.cost = std::make_unique<PointToPlaneFactor>(p.point_lidar, p.alpha, *plane, config.T_body_lidar);
        }
        r.loss = std::make_unique<ceres::HuberLoss>(config.huber_m / plane->sigma);
        scan.residuals.push_back(std::move(r));
      }
    }
  }

  // One solve of the window. The oldest scan's begin node is held constant (the gauge; stand-in for a
  // marginalization prior). Its end node stays free: holding it too would freeze the first scan's
  // (unknown, zero-guessed) sweep motion and make the motion prior fight the data. Returns false when the
  // solver fails.
  //
  // new_scan_only: the ICP rounds of a new scan move only its own nodes (every other node constant, only
  // its residuals and the motion priors that touch its nodes): a 12-parameter problem, cheap to repeat.
  bool Solve(int* iterations, bool new_scan_only = false) {
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.enable_fast_removal = false;
    ceres::Problem problem(problem_options);
    for (Node& node : nodes) problem.AddParameterBlock(node.pose.data(), kPoseSize, &manifold);
    const long first_free = new_scan_only ? window.back().begin_node : window.front().begin_node + 1;
    for (long id = first_node_id; id < first_free; ++id)
      problem.SetParameterBlockConstant(NodeAt(id).pose.data());
    // Motion priors on (id - 2, id - 1, id) touch a free node iff id >= first_free.
    for (long id = std::max(first_node_id + 2, first_free); id <= LastNodeId(); ++id) {
      Node& node = NodeAt(id);
      if (node.motion_prior)
        problem.AddResidualBlock(node.motion_prior.get(), nullptr, NodeAt(id - 2).pose.data(),
                                 NodeAt(id - 1).pose.data(), node.pose.data());
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
    ceres::Solver::Options options;
    options.linear_solver_type = new_scan_only ? ceres::DENSE_QR                 // 12 parameters
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

  void Release(ScanState& scan) {
    Keyframe keyframe;
    keyframe.stamp = scan.stamp + (scan.end - scan.stamp) / 2;
    const double alpha = scan.end > scan.stamp
                             ? static_cast<double>(keyframe.stamp - scan.stamp) / (scan.end - scan.stamp)
                             : 0;
    const SE3 begin = NodePose(scan.begin_node), end = NodePose(scan.end_node);
    keyframe.T_world_body = PoseAt(begin, end, alpha);
    if (scan.end > scan.stamp)
      keyframe.velocity = (end.translation() - begin.translation()) / ToSeconds(scan.end - scan.stamp);
    keyframe.scan_world.reserve(scan.points.size());
    keyframe.scan_intensity.reserve(scan.points.size());
    const SweepPoses sweep = Sweep(scan);
    for (const PreparedPoint& p : scan.points) {
      keyframe.scan_world.push_back((sweep.At(p.alpha) * p.point_lidar).cast<float>());
      keyframe.scan_intensity.push_back(p.intensity);
    }
    finished.push_back(std::move(keyframe));
  }

  // Releases the oldest scan and drops the nodes no remaining scan uses.
  void PopOldest() {
    Release(window.front());
    window.pop_front();
    const long keep_from = window.empty() ? LastNodeId() + 1 : window.front().begin_node;
    while (!nodes.empty() && first_node_id < keep_from) {
      nodes.pop_front();
      ++first_node_id;
    }
  }

  void InsertIntoMap(const ScanState& scan) {
    const std::vector<PreparedPoint> sparse = DownsamplePrepared(scan.points, config.map_insert_voxel_m);
    std::vector<Eigen::Vector3d> world;
    world.reserve(sparse.size());
    const SweepPoses sweep = Sweep(scan);
    for (const PreparedPoint& p : sparse) world.push_back(sweep.At(p.alpha) * p.point_lidar);
    map.Insert(world);
    map.RemoveFarFrom(NodePose(scan.end_node).translation());
  }

  Status AddScan(const LidarScan& scan);
};

Status LidarOdometry::Impl::AddScan(const LidarScan& input) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  stats = OdometryStats{};
  if (input.end < input.stamp)
    return Status::Error("lidar scan at " + StampText(input.stamp) + ": end before stamp");
  if (has_last && (input.stamp <= last_stamp || input.stamp < last_end - kSharedNodeTolerance)) {
    warnings.push_back("lidar scan at " + StampText(input.stamp) + " skipped: not after the previous scan (" +
                       StampText(last_stamp) + " .. " + StampText(last_end) + ")");
    return {};
  }
  ScanState scan;
  scan.stamp = input.stamp;
  scan.end = input.end;
  scan.points = PrepareScan(input, config.min_range_m, config.max_range_m);
  scan.registration_points = DownsamplePrepared(scan.points, config.input_voxel_m);
  if (static_cast<int>(scan.registration_points.size()) < config.min_points) {
    warnings.push_back("lidar scan at " + StampText(input.stamp) +
                       " skipped: " + std::to_string(scan.registration_points.size()) +
                       " usable points after filtering (of " + std::to_string(input.points.size()) +
                       "), need " + std::to_string(config.min_points));
    return {};
  }
  has_last = true;
  last_stamp = input.stamp;
  last_end = input.end;

  // Nodes: the very first sweep gets a single node at its middle: its motion is unknown (no map yet), so
  // it is mapped as if at rest, which is the pose at its middle to first order; two nodes would leave its
  // end node without data. Later sweeps share the previous end node when they start where it ended.
  if (window.empty() && nodes.empty()) {
    scan.begin_node = scan.end_node = AddNode(input.stamp + (input.end - input.stamp) / 2);
    window.push_back(std::move(scan));
    InsertIntoMap(window.back());
    stats.solve_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return {};
  }
  const bool share = !nodes.empty() && std::llabs(input.stamp - nodes.back().stamp) < kSharedNodeTolerance;
  scan.begin_node = share ? LastNodeId() : AddNode(input.stamp);
  scan.end_node = input.end - NodeAt(scan.begin_node).stamp >= kSharedNodeTolerance ? AddNode(input.end)
                                                                                    : scan.begin_node;
  const bool first = window.empty();
  window.push_back(std::move(scan));
  ScanState& current = window.back();

  bool accepted = true;
  if (!first) {
    std::vector<PoseArray> saved;
    for (const Node& node : nodes) saved.push_back(node.pose);
    const SE3 guess = NodePose(current.end_node);
    bool solved = true;
    // ICP-style: re-query the planes after each solve until the new scan's begin and end poses move less than
    // kConvergedTranslation / kConvergedRotation in a round, or association_rounds is reached.
    for (int round = 0; round < config.association_rounds && solved; ++round) {
      const SE3 begin_before = NodePose(current.begin_node), end_before = NodePose(current.end_node);
      Associate(current);
      solved = Solve(&stats.iterations, /*new_scan_only=*/true);
      const SE3 step_begin = begin_before.inverse() * NodePose(current.begin_node);
      const SE3 step_end = end_before.inverse() * NodePose(current.end_node);
      if (std::max(step_begin.translation().norm(), step_end.translation().norm()) < kConvergedTranslation &&
          std::max(step_begin.so3().angle(), step_end.so3().angle()) < kConvergedRotation)
        break;
    }
    if (solved && config.window_size > 2) solved = Solve(&stats.iterations);  // the whole window, once
    stats.residuals = static_cast<int>(current.residuals.size());
    bool finite = true;
    for (const Node& node : nodes)
      finite = finite && Eigen::Map<const Eigen::Matrix<double, 7, 1>>(node.pose.data()).allFinite();
    const SE3 solved_end = finite ? NodePose(current.end_node) : SE3();
    const SE3 correction = guess.inverse() * solved_end;
    if (!solved || !finite || correction.translation().norm() > config.max_correction_m ||
        correction.so3().angle() > config.max_correction_rad || current.residuals.size() < 6) {
      std::size_t i = 0;
      for (Node& node : nodes) node.pose = saved[i++];
      current.residuals.clear();
      accepted = false;
      warnings.push_back(
          "lidar scan at " + StampText(input.stamp) +
          ": registration rejected (solver failure, too few planes or implausible jump); kept the "
          "constant-velocity guess");
    }
  }
  if (accepted) InsertIntoMap(current);
  while (static_cast<int>(window.size()) > config.window_size) PopOldest();
  stats.solve_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return {};
}

LidarOdometry::LidarOdometry(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LidarOdometry::LidarOdometry(LidarOdometry&&) noexcept = default;
LidarOdometry& LidarOdometry::operator=(LidarOdometry&&) noexcept = default;
LidarOdometry::~LidarOdometry() = default;

Expected<LidarOdometry> LidarOdometry::Create(const LidarOdometryConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return status;
  return LidarOdometry(std::make_unique<Impl>(config));
}

Status LidarOdometry::AddScan(const LidarScan& scan) { return impl_->AddScan(scan); }

std::vector<Keyframe> LidarOdometry::TakeFinished() {
  std::vector<Keyframe> out = std::move(impl_->finished);
  impl_->finished.clear();
  return out;
}

void LidarOdometry::Finish() {
  if (impl_->window.size() >= 2) {
    std::vector<PoseArray> saved;
    for (const Node& node : impl_->nodes) saved.push_back(node.pose);
    int iterations = 0;
    bool finite = impl_->Solve(&iterations);
    for (const Node& node : impl_->nodes)
      finite = finite && Eigen::Map<const Eigen::Matrix<double, 7, 1>>(node.pose.data()).allFinite();
    if (!finite) {
      std::size_t i = 0;
      for (Node& node : impl_->nodes) node.pose = saved[i++];
      impl_->warnings.push_back("final window solve failed; kept the previous estimate");
    }
  }
  while (!impl_->window.empty()) impl_->PopOldest();
}

const std::vector<std::string>& LidarOdometry::warnings() const { return impl_->warnings; }
const OdometryStats& LidarOdometry::last_stats() const { return impl_->stats; }

}  // namespace uf::estimator
