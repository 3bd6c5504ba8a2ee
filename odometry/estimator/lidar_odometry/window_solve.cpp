// Solving the window and marginalizing its oldest states (see odometry_window.h): which blocks move and
// which factors take part; the graph (window/factor_graph.h) does the rest.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "odometry/estimator/factors/wheel_factor.h"
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
//
// rigid_sweep (with new_scan_only): the rounds of a rigid sweep (Rounds::rigid): only the scan's end node
// moves (6 dof), with only the scan's point-to-plane factors.
bool LidarOdometry::Impl::Solve(int* iterations, bool new_scan_only, bool rigid_sweep) {
  const StageTimer timer(new_scan_only ? stats.register_ms : stats.window_ms);
  WindowSolveRequest request;
  request.use_prior = graph.prior() && !new_scan_only;
  const long first_free = new_scan_only       ? window.back().begin_node
                          : request.use_prior ? first_node_id
                                              : window.front().begin_node + 1;
  for (long id = first_node_id; id <= LastNodeId(); ++id) {
    Node& node = NodeAt(id);
    if (id >= first_free && (!rigid_sweep || id == window.back().end_node))
      request.free.push_back(node.pose.data());
    // Without a prior the oldest state's speed and biases stay free: only its pose fixes the gauge.
    if (inertial && !rigid_sweep && (id >= first_free || (!new_scan_only && id >= window.front().begin_node)))
      request.free.push_back(node.speed_bias.data());
  }
  if (wheel && wheel->scale_free() && !new_scan_only && WheelScaleObservable())
    request.free.push_back(wheel->scale_block());
  if (gnss && !new_scan_only)
    for (double* block : gnss->StateBlocks()) request.free.push_back(block);
  if (visual && !new_scan_only) visual->AppendFreeBlocks(request.free);
  const bool lever_free = LeverFactors() && !new_scan_only && LeverExcited();  // window_extrinsic.cpp
  if (lever_free) request.free.push_back(lidar_translation.data());
  const std::array<double, 3> lever_before = lidar_translation;
  if (new_scan_only) {  // the registration: the new scan's planes, and the motion factors at its nodes
    const long scan = window.back().id;
    request.use = [scan, rigid_sweep](const Factor& f) {
      if (rigid_sweep) return f.kind == FactorKind::kLidar && f.tag == scan;
      return f.kind == FactorKind::kLidar ? f.tag == scan : f.kind != FactorKind::kVisual;
    };
  }
  const bool camera_budget = visual && !new_scan_only;
  request.max_iterations = camera_budget ? config.visual.max_iterations : config.max_iterations;
  request.max_time_s = camera_budget ? config.visual.max_solver_time_s : config.max_solver_time_s;
  // The scans' factors condensed (window/condensed_factor.h), unless a scan is taken through a projector
  // (reliability scheduling): the projector drops Jacobian columns, not the residuals' dependence on the weak
  // directions, so a solve on the residuals still weighs steps along them by the cost they change, where a
  // model of the projected Jacobians would leave them to the other factors entirely (docs/METHOD.md "Sliding
  // window and solve": LWIO in the corridor lost 20-80 %). Condensing only the other scans would solve the
  // window twice on the projected ones' residuals whenever a model is renewed.
  const auto projected = [this] {
    return std::any_of(window.begin(), window.end(), [](const ScanState& s) { return s.projector.has_value(); });
  };
  if (!new_scan_only && config.condensed_lidar_rounds > 0 && !projected()) {
    request.condense = [](const Factor& f) { return f.kind == FactorKind::kLidar; };
    request.condensed_rounds = config.condensed_lidar_rounds;
    request.condense_config = config.marginalization;
  }
  const WindowSolveResult result = graph.Solve(request);
  *iterations += result.iterations;
  if (LeverFactors() && !new_scan_only) {
    ++lever_solves;
    lever_free_solves += lever_free ? 1 : 0;
    const Eigen::Map<const Eigen::Vector3d> t_BL(lidar_translation.data());
    if (!result.usable || !t_BL.allFinite()) lidar_translation = lever_before;
    config.T_body_lidar = SE3(config.T_body_lidar.so3(), t_BL);  // what the sweeps and the map use
    if (lever_free) {
      recent_lever.push_back(t_BL);
      if (recent_lever.size() > kLeverSettleSolves) recent_lever.pop_front();
    }
  }
  return result.usable;
}

// Whether the LiDAR observes the wheel scale over the window (docs/METHOD.md "Wheel factor"). The scale is
// the ratio of the distance driven to the distance the wheel reports. Besides the wheel, only the LiDAR
// measures that distance: the IMU sees it only through the accelerations, where the scale is confounded with
// the accelerometer bias (driving off from rest with acceleration a, a bias error b makes the wheel look
// scaled by 1 - b / a). So the scale is left free only where the LiDAR pins the forward motion, by two tests
// on the window's scans, each with its LiDAR standard deviation sigma_k along the wheel's forward axis
// (ScanState::forward_sigma_m) at the distance d_k driven:
//  - the LiDAR constrains the forward direction at least as well as the wheel does over the same intervals:
//    sum_k 1 / sigma_k^2 >= sum_k 1 / sigma_wheel,k^2 (sigma_wheel,k: the forward standard deviation of the
//    wheel factors across scan k). In a corridor or a tunnel the LiDAR is degenerate along the axis (sigma_k
//    of several cm against the wheel's 1.6 cm per 0.1 s, LWIO's forward_velocity_density of 0.05) and cannot
//    calibrate the wheel; on urban streets it is a few mm against the wheel's 1.6 cm.
//  - the LiDAR alone would know the scale at least as well as its prior: fitting the scale to the positions
//    is a weighted linear regression of position on d_k, whose slope has the variance
//    1 / sum_k w_k (d_k - d_mean)^2 (w_k = 1 / sigma_k^2, d_mean the w-weighted mean), which must be at
//    most scale_prior_sigma^2; at a standstill or a crawl nothing observes the scale.
// Otherwise the scale block is held at its current value for the solve.
bool LidarOdometry::Impl::WheelScaleObservable() {
  std::unordered_map<long, double> wheel_variance;  // forward variance of the wheel factor ending at a node
  for (const Factor& factor : graph.Entries(FactorKind::kWheel)) {
    if (const auto* cost = dynamic_cast<const WheelFactor*>(factor.cost.get()))
      wheel_variance[factor.tag] = cost->preintegration().covariance()(kWheelPosition, kWheelPosition);
  }
  double lidar_information = 0, wheel_information = 0;
  double sum_w = 0, sum_wd = 0, sum_wdd = 0, distance = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < window.size(); ++k) {
    const ScanState& scan = window[k];
    const Eigen::Vector3d position = NodePose(scan.end_node).translation();
    if (k > 0) distance += (position - previous).norm();
    previous = position;
    const double sigma = scan.forward_sigma_m;
    if (!std::isfinite(sigma) || sigma <= 0) continue;
    double variance = 0;  // the wheel's, over the scan
    bool covered = scan.end_node > scan.begin_node;
    for (long id = scan.begin_node + 1; id <= scan.end_node; ++id) {
      const auto it = wheel_variance.find(id);
      if (it == wheel_variance.end()) {
        covered = false;
        break;
      }
      variance += it->second;
    }
    if (!covered || variance <= 0) continue;
    const double w = 1.0 / (sigma * sigma);
    lidar_information += w;
    wheel_information += 1.0 / variance;
    sum_w += w;
    sum_wd += w * distance;
    sum_wdd += w * distance * distance;
  }
  if (sum_w <= 0 || lidar_information < wheel_information) return false;
  const double spread = sum_wdd - sum_wd * sum_wd / sum_w;
  const double prior = config.wheel.scale_prior_sigma;
  return spread > 0 && 1.0 <= spread * prior * prior;
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
  // The landmarks leave with their anchors, dropped with their factors rather than marginalized
  // (docs/METHOD.md "LiDAR-visual-inertial odometry": folded into the prior they made the estimated camera
  // time offset run away, for no gain in accuracy).
  graph.RemoveBlocks(AnchoredBlocks(keep_from));
  std::vector<double*> leaving;
  for (long id = first_node_id; id < keep_from && id <= LastNodeId(); ++id) {
    leaving.push_back(NodeAt(id).pose.data());
    leaving.push_back(NodeAt(id).speed_bias.data());
  }
  // The receiver's offsets at the leaving nodes leave with them.
  const long last_leaving = std::min(keep_from, LastNodeId() + 1) - 1;
  const bool offsets_leave = gnss && last_leaving >= first_node_id;
  if (offsets_leave)
    for (double* offset : gnss->OffsetBlocksUpTo(NodeAt(last_leaving).stamp)) leaving.push_back(offset);
  if (!config.marginalize || keep_from > LastNodeId()) {
    graph.RemoveBlocks(leaving);
  } else if (Status s = graph.Marginalize(leaving, config.marginalization); !s.ok()) {
    // Without a prior the window falls back to holding its oldest pose constant: less information, no harm.
    warnings.push_back("marginalization at " + StampText(stamp) + " failed, prior dropped: " + s.message());
  }
  if (offsets_leave) gnss->DropOffsetsUpTo(NodeAt(last_leaving).stamp);
  ForgetVisualBefore(keep_from);
}

}  // namespace uf::estimator
