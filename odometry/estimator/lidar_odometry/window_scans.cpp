// The scans of the window: association with the map, map updates, keyframe release (see odometry_window.h).
#include <ceres/loss_function.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/factors/projected_factor.h"
#include "odometry/estimator/lidar_odometry/odometry_window.h"
#include "odometry/estimator/providers/imu_reliability.h"
#include "odometry/estimator/schedule/lidar_degeneracy.h"

namespace uf::estimator {
namespace {

constexpr double kOnPlaneSigmas = 2;  // a point this many plane sigmas from its plane lies on it

}  // namespace

LidarOdometry::Impl::SweepEnds LidarOdometry::Impl::EndsOf(const ScanState& scan) const {
  if (const std::optional<std::pair<SE3, SE3>> ends = ExtrapolatedSweepEnds(scan))
    return {ends->first, ends->second, false};
  return {NodePose(scan.begin_node), NodePose(scan.end_node), scan.begin_node == scan.end_node};
}

SweepPoses LidarOdometry::Impl::Sweep(const SweepEnds& ends) const {
  return SweepPoses(ends.begin, ends.end, config.T_body_lidar, ends.single);
}

// A sweep with one node (the first of a local map) was mapped as if at rest: its motion was not known. Once
// nodes after it exist (the next scans'), the motion to the latest of them within kMaxExtrapolation sweeps,
// extrapolated at constant velocity over the sweep, gives its begin and end poses: with n the node at time
// t_n and m that one,
//   T(t) = PoseAt(T_n, T_m, (t - t_n) / (t_m - t_n)),  t in [stamp, end]
// (a fraction outside [0, 1] extrapolates along the same geodesic). The latest node, not the next: the
// extrapolation multiplies m's error by sweep / (2 (t_m - t_n)), and the next node lies only half a sweep
// away. None for a sweep with two nodes, while there is no later node, when the sweep has no duration, or
// when the next node is already more than kMaxExtrapolation sweeps away (a gap: its motion says little).
std::optional<std::pair<SE3, SE3>> LidarOdometry::Impl::ExtrapolatedSweepEnds(const ScanState& scan) const {
  constexpr double kMaxExtrapolation = 2;
  const long n = scan.begin_node;
  if (scan.end_node != n || scan.end <= scan.stamp || n >= LastNodeId()) return std::nullopt;
  const Stamp reach = NodeAt(n).stamp + (scan.end - scan.stamp) * kMaxExtrapolation;
  long m = n;
  while (m < LastNodeId() && NodeAt(m + 1).stamp <= reach) ++m;
  if (m == n || NodeAt(m).stamp <= NodeAt(n).stamp) return std::nullopt;
  const SE3 here = NodePose(n), there = NodePose(m);
  const auto fraction = [&](Stamp t) {
    return static_cast<double>(t - NodeAt(n).stamp) / static_cast<double>(NodeAt(m).stamp - NodeAt(n).stamp);
  };
  return std::make_pair(PoseAt(here, there, fraction(scan.stamp)), PoseAt(here, there, fraction(scan.end)));
}

// The first sweep of a local map, mapped as if at rest, leaves its planes smeared along the motion (a 5 m/s
// start: 0.5 m over a 0.1 s sweep), and the next scans register against them centimetres off. While that
// sweep is still in the window (so is every scan of the map), each registration gives its motion anew
// (ExtrapolatedSweepEnds) and moves the window's poses: the map is rebuilt from the window's scans at their
// poses now and their associations redone, when that sweep moved a point kRange away by more than kSmear
// (a start at rest leaves the map as it was: rebuilt, a corridor's LIO came out 0.091 m instead of 0.072 m).
// Once that sweep has left the window, the map keeps scans the window no longer holds.
void LidarOdometry::Impl::RemapFirstSweep() {
  constexpr double kRange = 10, kSmear = 0.01;  // m: a point this far moving this much over the sweep
  const ScanState& first = window.front();
  const std::optional<std::pair<SE3, SE3>> ends = first.in_map ? ExtrapolatedSweepEnds(first) : std::nullopt;
  if (!ends) return;
  const SE3 motion = ends->first.inverse() * ends->second;
  if (motion.translation().norm() + kRange * motion.so3().Log().norm() > kSmear) RebuildMap();
}

void LidarOdometry::Impl::RebuildMap() {
  map.Clear();
  for (ScanState& scan : window)
    if (scan.in_map) InsertIntoMap(scan);
  for (ScanState& scan : window)
    if (scan.in_map && scan.begin_node != scan.end_node) Associate(scan);
}

// Point-to-plane residuals of `scan` against the map at the current node poses: up to
// max_residuals_per_scan points with a plane, visited at an even stride (then the offsets in between) so
// that they spread over the whole scan. The planes of a batch of points are found in parallel (the map's
// queries are const), then the batch is taken in visiting order until the cap: the same residuals as a
// serial pass.
//
// rounds: against the coarse map, with the wider robust kernel, or with the sweep rigid (Rounds). Rigid,
// each point's factor is on the end node alone, the point taken into the end node's body frame along the
// sweep as it is now, T_end^-1 T_world_lidar(alpha) p; moving the end node by G moves every pose of the sweep
// by G.
void LidarOdometry::Impl::Associate(ScanState& scan, Rounds rounds) {
  const StageTimer timer(stats.associate_ms);
  const bool coarse = rounds.coarse, rigid = rounds.rigid;
  const VoxelHashMap& map = coarse ? CoarseMap() : this->map;
  const double max_plane_distance_m = config.max_plane_distance_m * (coarse ? kCoarseScale : 1.0);
  const double huber_m = config.huber_m * (rounds.wide_kernel ? kCoarseScale : 1.0);
  graph.Remove(FactorKind::kLidar, scan.id);
  scan.residuals = scan.visited = scan.on_plane = 0;
  const auto& points = scan.registration_points;
  const std::size_t n = points.size(), cap = static_cast<std::size_t>(config.max_residuals_per_scan);
  const std::size_t step = std::max<std::size_t>(1, n / cap);
  const bool single = scan.begin_node == scan.end_node;
  // With the translation estimated (LeverFactors), the factors take it from its block; not through a
  // projector (ProjectedFactor takes pose blocks only) nor for a rigid sweep (only its end node moves).
  const bool lever = LeverFactors() && !rigid && !scan.projector;
  const Eigen::Matrix3d R_body_lidar = config.T_body_lidar.so3().matrix();
  const SweepPoses sweep = Sweep(scan);
  const SE3 T_end_world = NodePose(scan.end_node).inverse();  // for a rigid sweep
  std::vector<double*> blocks = {NodeAt(rigid ? scan.end_node : scan.begin_node).pose.data()};
  if (!single && !rigid) blocks.push_back(NodeAt(scan.end_node).pose.data());
  if (lever) blocks.push_back(lidar_translation.data());
  if (scan.plane_cache.size() != n || scan.plane_cache_revision != map.revision() ||
      scan.plane_cache_coarse != coarse) {
    scan.plane_cache.assign(n, {});
    scan.plane_cache_revision = map.revision();
    scan.plane_cache_coarse = coarse;
  }
  std::vector<std::size_t> order;  // point indices in visiting order
  order.reserve(n);
  for (std::size_t offset = 0; offset < step; ++offset)
    for (std::size_t i = offset; i < n; i += step) order.push_back(i);
  // Per point: no plane within max_plane_distance_m (no residual), a plane near it, or the point on it
  // (within kOnPlaneSigmas of the plane's sigma: the registration's quality, ScanState::MatchFraction).
  enum : char { kNoPlane, kNearPlane, kOnPlane };
  std::vector<char> usable(order.size(), kNoPlane);
  std::size_t next = 0;
  while (next < order.size() && static_cast<std::size_t>(scan.residuals) < cap) {
    // A batch a little larger than the residuals still wanted; where fewer of its points find a plane (on
    // KITTI about a third do), the next batch goes on from there.
    const std::size_t wanted = cap - static_cast<std::size_t>(scan.residuals);
    const std::size_t end = std::min(order.size(), next + wanted + wanted / 4 + 64);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(next, end, 64), [&](const auto& range) {
      for (std::size_t k = range.begin(); k < range.end(); ++k) {
        const std::size_t i = order[k];
        const Eigen::Vector3d p_world = sweep.At(points[i].alpha) * points[i].point_lidar;
        ScanState::CachedPlane& cached = scan.plane_cache[i];
        const std::uint64_t key = map.QueryKey(p_world);
        if (!cached.known || cached.key != key) {
          cached.plane = map.PlaneNear(p_world);
          cached.key = key;
          cached.known = true;
        }
        // Correspondence gate: a plane farther than max_plane_distance_m from the point is another surface.
        const std::optional<Plane>& plane = cached.plane;
        if (!plane) {
          usable[k] = kNoPlane;
          continue;
        }
        const double distance = std::abs(plane->normal.dot(p_world - plane->point));
        usable[k] = distance > max_plane_distance_m             ? kNoPlane
                    : distance <= kOnPlaneSigmas * plane->sigma ? kOnPlane
                                                                : kNearPlane;
      }
    });
    for (; next < end && static_cast<std::size_t>(scan.residuals) < cap; ++next) {
      if (usable[next] == kNoPlane) continue;
      if (usable[next] == kOnPlane) ++scan.on_plane;
      const PreparedPoint& p = points[order[next]];
      const Plane& plane = *scan.plane_cache[order[next]].plane;
      std::unique_ptr<ceres::CostFunction> cost;
      if (rigid) {
        cost = std::make_unique<PointToPlaneFactorSinglePose>(
            T_end_world * (sweep.At(p.alpha) * p.point_lidar), plane);
      } else if (lever && single) {
        cost = std::make_unique<PointToPlaneLeverFactorSinglePose>(p.point_lidar, plane, R_body_lidar);
      } else if (lever) {
        cost = std::make_unique<PointToPlaneLeverFactor>(p.point_lidar, p.alpha, plane, R_body_lidar);
      } else if (single) {
        cost = std::make_unique<PointToPlaneFactorSinglePose>(config.T_body_lidar * p.point_lidar, plane);
      } else {
        cost = std::make_unique<PointToPlaneFactor>(p.point_lidar, p.alpha, plane, config.T_body_lidar);
      }
      if (scan.projector) cost = std::make_unique<ProjectedFactor>(std::move(cost), *scan.projector);
      graph.Add(FactorKind::kLidar, scan.id, std::move(cost),
                std::make_unique<ceres::HuberLoss>(huber_m / plane.sigma), blocks, /*anchors=*/true);
      ++scan.residuals;
    }
  }
  scan.visited = static_cast<int>(next);
}

// The coarse map, brought up to date with the map when it changed: the map seen through voxels kCoarseScale
// times larger (VoxelHashMap::Coarsened: their moments are those of every point the map keeps), so that a
// plane query reaches surfaces that far from a point (a 3x3x3 block 6 m wide at the default 0.5 m voxels).
// Built only when a far guess needs it.
const VoxelHashMap& LidarOdometry::Impl::CoarseMap() {
  if (!coarse_map || coarse_map_revision != map.revision()) {
    VoxelMapConfig coarse = config.map;
    coarse.voxel_m *= kCoarseScale;
    coarse.min_plane_sigma_m *= kCoarseScale;
    coarse.neighbour_weight = 1.0;  // the whole block: a coarse plane is there to reach far surfaces
    coarse_map = std::make_unique<VoxelHashMap>(map.Coarsened(kCoarseScale, coarse));
    coarse_map_revision = map.revision();
  }
  return *coarse_map;
}

void LidarOdometry::Impl::InsertIntoMap(ScanState& scan) {
  const StageTimer timer(stats.map_ms);
  std::vector<Eigen::Vector3d> world;
  std::vector<int> rings;
  world.reserve(scan.map_points.size());
  rings.reserve(scan.map_points.size());
  const SweepPoses sweep = Sweep(scan);
  for (const PreparedPoint& p : scan.map_points) {
    world.push_back(sweep.At(p.alpha) * p.point_lidar);
    rings.push_back(p.ring);
  }
  map.Insert(world, rings);
  map.RemoveFarFrom(NodePose(scan.end_node).translation());
  scan.in_map = true;
}

void LidarOdometry::Impl::Release(ScanState& scan) {
  Keyframe keyframe;
  keyframe.stamp = scan.stamp + (scan.end - scan.stamp) / 2;
  const double alpha =
      scan.end > scan.stamp ? static_cast<double>(keyframe.stamp - scan.stamp) / (scan.end - scan.stamp) : 0;
  const SweepEnds ends = EndsOf(scan);
  keyframe.T_world_body = PoseAt(ends.begin, ends.end, alpha);
  if (inertial) {
    const NavState b = NodeState(scan.begin_node), e = NodeState(scan.end_node);
    keyframe.velocity = (1 - alpha) * b.velocity + alpha * e.velocity;
    keyframe.bias_acc = b.accel_bias;
    keyframe.bias_gyro = b.gyro_bias;
    keyframe.inertial = true;
    if (LeverFactors()) keyframe.lidar_translation = config.T_body_lidar.translation();
  } else if (scan.end > scan.stamp) {
    keyframe.velocity =
        (ends.end.translation() - ends.begin.translation()) / ToSeconds(scan.end - scan.stamp);
  }
  // A scan whose registration was rejected keeps its predicted pose but brings no points: where they lie is
  // not known.
  const std::size_t n = scan.in_map ? scan.points.size() : 0;
  keyframe.scan_world.resize(n);
  keyframe.scan_intensity.resize(n);
  const SweepPoses sweep = Sweep(ends);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const PreparedPoint& p = scan.points[i];
      keyframe.scan_world[i] = (sweep.At(p.alpha) * p.point_lidar).cast<float>();
      keyframe.scan_intensity[i] = p.intensity;
    }
  });
  if (scan.information)
    keyframe.lidar_degeneracy = AnalyzeLidarInformation(*scan.information, scan.residuals);
  if (inertial) keyframe.imu_reliability = ScoreImuFactor(graph, scan.end_node);
  if (wheel) keyframe.wheel_consistency = wheel->TakeConsistency(scan.end_node);
  if (gnss) keyframe.gnss_checks = gnss->TakeChecks(NodeAt(scan.end_node).stamp);
  if (visual) keyframe.camera_checks = visual->TakeChecks(NodeAt(scan.end_node).stamp);
  if (!config.use_imu || inertial) {
    Emit(std::move(keyframe));
    return;
  }
  // LIO not yet initialized: the pose is in the LO frame (the first IMU pose's), which the alignment will
  // rotate into the gravity-aligned world. Released now, the trajectory and the map would carry the start's
  // tilt up to the alignment and jump there (KITTI raw 0009: 3.8 deg of roll). Held keyframes are rotated
  // with the window (ApplyInertialAlignment); past kMaxHeldKeyframes the oldest leave as they are, with a
  // warning.
  held_for_alignment.push_back(std::move(keyframe));
  if (held_for_alignment.size() > kMaxHeldKeyframes) {
    if (!released_unaligned)
      warnings.push_back("LIO not initialized after " + std::to_string(kMaxHeldKeyframes) +
                         " keyframes: releasing them in the LO frame from " +
                         StampText(held_for_alignment.front().stamp) +
                         " on (the trajectory tilts where the initialization comes)");
    released_unaligned = true;
    Emit(std::move(held_for_alignment.front()));
    held_for_alignment.pop_front();
  }
}

// The held keyframes into the world: poses, velocities and points turned by T_world_lo.
void LidarOdometry::Impl::ReleaseHeld(const SE3& T_world_lo) {
  const Eigen::Matrix3f R = T_world_lo.so3().matrix().cast<float>();
  const Eigen::Vector3f t = T_world_lo.translation().cast<float>();
  for (Keyframe& keyframe : held_for_alignment) {
    keyframe.T_world_body = T_world_lo * keyframe.T_world_body;
    keyframe.velocity = T_world_lo.so3() * keyframe.velocity;
    for (Eigen::Vector3f& p : keyframe.scan_world) p = R * p + t;
    Emit(std::move(keyframe));
  }
  held_for_alignment.clear();
}

// The Gauss-Newton information of the scan's point-to-plane factors, H = sum rho' J^T J (rho': the Huber
// weight at the residual), for a rigid move of the scan (the same tangent step [dt; dtheta] on its begin
// and end node, J = J_b + J_e).
Matrix6d LidarOdometry::Impl::ScanInformation(const ScanState& scan) {
  Matrix6d H = Matrix6d::Zero();
  for (const Factor& factor : graph.Entries(FactorKind::kLidar)) {
    if (factor.tag != scan.id) continue;
    const auto* cost = dynamic_cast<const TangentJacobianCost*>(factor.cost.get());
    if (cost == nullptr) continue;
    // Blocks: one or two poses, then the lever arm's (PointToPlaneLeverFactor), which is left out here.
    const double* parameters[3] = {};
    Eigen::Matrix<double, 1, 6> J_b, J_e = Eigen::Matrix<double, 1, 6>::Zero();
    double* jacobians[3] = {J_b.data(), nullptr, nullptr};
    for (std::size_t i = 0; i < factor.blocks.size() && i < 3; ++i) parameters[i] = factor.blocks[i];
    if (factor.blocks.size() > 1 && graph.IsPoseBlock(factor.blocks[1])) jacobians[1] = J_e.data();
    double r = 0;
    if (!cost->EvaluateTangent(parameters, &r, jacobians)) continue;
    double rho[3] = {r * r, 1.0, 0.0};
    if (factor.loss) factor.loss->Evaluate(r * r, rho);
    const Eigen::Matrix<double, 1, 6> J = J_b + J_e;
    H.noalias() += rho[1] * J.transpose() * J;
  }
  return H;
}

// Reliability scheduling of the LiDAR (docs/METHOD.md "Factor-wise reliability scheduling"): the scan's
// factors are taken through the projector of its weak directions from now on, so that the window solves and
// the marginalization get no LiDAR information along them.
void LidarOdometry::Impl::DropWeakDirections(ScanState& scan) {
  if (scan.information) Project(scan, WeakDirectionProjector(*scan.information));
}

// The same for the translations the wheel holds better over the scan's last node interval
// (WheelProvider::PositionInformation), where wheel samples cover the interval. Also while the wheel's gate
// leaves the interval's factor out: handing the axis back to the scan then pulled the window towards the map
// it had drifted with, which kept the wheel disagreeing and its gate shut (docs/METHOD.md "Factor-wise
// reliability scheduling").
void LidarOdometry::Impl::LeaveWeakTranslationsToWheel(ScanState& scan) {
  const long id = scan.end_node;
  if (!scan.information || id <= first_node_id || wheel->CoveredUntil() < NodeAt(id).stamp) return;
  const double dt = ToSeconds(NodeAt(id).stamp - NodeAt(id - 1).stamp);
  if (!(dt > 0)) return;
  const Eigen::Matrix3d W = wheel->PositionInformation(NodePose(id).so3(), dt);
  if (Project(scan, LooseTranslationProjector(*scan.information, W))) ++scans_leaving_translations_to_wheel;
}

bool LidarOdometry::Impl::Project(ScanState& scan, const Matrix6d& P) {
  if (P.isIdentity(0.0)) return false;
  scan.projector = P;
  if (LeverFactors()) {  // a projected factor takes pose blocks only: made again without the lever's block
    Associate(scan);
    return true;
  }
  graph.ReplaceCosts(FactorKind::kLidar, scan.id, [&P](std::unique_ptr<ceres::CostFunction> cost) {
    return std::unique_ptr<ceres::CostFunction>(std::make_unique<ProjectedFactor>(std::move(cost), P));
  });
  return true;
}

// The standard deviation of the scan's position along the wheel's forward axis f = R_world_body R_body_wheel
// e_x that its own point-to-plane factors give (their information at registration, ScanInformation): the
// variance [f; 0]^T H^-1 [f; 0], the rotation free. Infinite where H leaves f unconstrained (no planes; a
// straight corridor without a feature along its axis).
double LidarOdometry::Impl::ForwardSigma(const ScanState& scan) const {
  if (!scan.information) return std::numeric_limits<double>::infinity();
  const Matrix6d& H = *scan.information;
  Vector6d e = Vector6d::Zero();
  e.head<3>() = NodePose(scan.end_node).rotation() * config.T_body_wheel.rotation().col(0);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(H);
  const double largest = eigen.eigenvalues().maxCoeff();
  double variance = 0;
  for (int i = 0; i < 6; ++i) {
    const double along = eigen.eigenvectors().col(i).dot(e);
    if (eigen.eigenvalues()(i) <= 1e-12 * largest) {
      if (std::abs(along) > 1e-9) return std::numeric_limits<double>::infinity();
      continue;
    }
    variance += along * along / eigen.eigenvalues()(i);
  }
  return largest > 0 ? std::sqrt(variance) : std::numeric_limits<double>::infinity();
}

void LidarOdometry::Impl::PopOldest() {
  Release(window.front());
  const long keep_from = window.size() > 1 ? window[1].begin_node : LastNodeId() + 1;
  MarginalizeBefore(keep_from, window.front().stamp);
  window.pop_front();
  while (!nodes.empty() && first_node_id < keep_from) {
    nodes.pop_front();
    ++first_node_id;
  }
  TrimStreams();
}

}  // namespace uf::estimator
