#include "odometry/estimator/lidar_odometry/lidar_odometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {
namespace {

constexpr double kConvergedTranslation = 0.005;  // m, registration converged when a round moves less
constexpr double kConvergedRotation = 0.001;     // rad

}  // namespace

Status LidarOdometry::Impl::AddScan(const LidarScan& input) {
  if (input.end < input.stamp)
    return Status::Error("lidar scan at " + StampText(input.stamp) + ": end before stamp");
  if (!config.use_imu && !config.use_wheel) {
    ProcessScan(input);
    return {};
  }
  pending.push_back(input);
  ProcessReady(/*flush=*/false);
  return {};
}

// LIO (or with wheel factors): a scan is processed once the IMU (and the wheel) cover its end, or once a
// scan more than imu_max_wait_s newer is waiting (a stream stalled: the scan goes ahead, the gap is
// bridged), or at the end of the data.
void LidarOdometry::Impl::ProcessReady(bool flush) {
  while (!pending.empty()) {
    const LidarScan& scan = pending.front();
    const bool covered =
        (!config.use_imu || imu.CoveredUntil() >= scan.end) && (!wheel || wheel->CoveredUntil() >= scan.end);
    const bool stalled = pending.back().stamp - scan.end > FromSeconds(config.imu_max_wait_s);
    if (!flush && !covered && !stalled) return;
    ProcessScan(scan);
    pending.pop_front();
  }
}

// One scan, as the method section reads: prepare it, give it begin/end nodes (guessed by the IMU or the
// constant-velocity model), register it against the map, update the map, initialize LIO when due, and let
// the oldest scan leave the window into the marginalization prior.
void LidarOdometry::Impl::ProcessScan(const LidarScan& input) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  stats = OdometryStats{};
  stats.stamp = input.stamp;
  if (has_last && (input.stamp <= last_stamp || input.stamp < last_end - kSharedNodeTolerance)) {
    warnings.push_back("lidar scan at " + StampText(input.stamp) + " skipped: not after the previous scan (" +
                       StampText(last_stamp) + " .. " + StampText(last_end) + ")");
    return;
  }
  ScanState scan;
  scan.id = next_scan_id++;
  scan.stamp = input.stamp;
  scan.end = input.end;
  {
    const StageTimer timer(stats.prepare_ms);
    scan.points = PrepareScan(input, config.min_range_m, config.max_range_m);
    scan.map_points = DownsamplePrepared(scan.points, config.map_insert_voxel_m);
    // When the map's voxels nest in the registration voxels, the first point of a registration voxel is the
    // first of its map voxel too: downsampling the (far fewer) map points gives the same registration
    // points.
    const double ratio = config.input_voxel_m / config.map_insert_voxel_m;
    const bool nested = ratio >= 1 && std::abs(ratio - std::round(ratio)) < 1e-9;
    scan.registration_points =
        DownsamplePrepared(nested ? scan.map_points : scan.points, config.input_voxel_m);
  }
  if (static_cast<int>(scan.registration_points.size()) < config.min_points) {
    warnings.push_back("lidar scan at " + StampText(input.stamp) +
                       " skipped: " + std::to_string(scan.registration_points.size()) +
                       " usable points after filtering (of " + std::to_string(input.points.size()) +
                       "), need " + std::to_string(config.min_points));
    return;
  }
  has_last = true;
  last_stamp = input.stamp;
  last_end = input.end;

  // Nodes: the very first sweep gets a single node at its middle: its motion is unknown (no map yet), so
  // it is mapped as if at rest, which is the pose at its middle to first order; two nodes would leave its
  // end node without data. Later sweeps share the previous end node when they start where it ended.
  if (nodes.empty()) {
    scan.begin_node = scan.end_node = AddNode(input.stamp + (input.end - input.stamp) / 2);
    window.push_back(std::move(scan));
    InsertIntoMap(window.back());
  } else {
    const bool share = std::llabs(input.stamp - nodes.back().stamp) < kSharedNodeTolerance;
    scan.begin_node = share ? LastNodeId() : AddNode(input.stamp);
    scan.end_node = input.end - NodeAt(scan.begin_node).stamp >= kSharedNodeTolerance ? AddNode(input.end)
                                                                                      : scan.begin_node;
    window.push_back(std::move(scan));
    if (RegisterNewScan(window.back())) InsertIntoMap(window.back());
    if (config.use_imu && !inertial) TryInitializeInertial();
  }
  if (std::optional<std::string> why;
      config.use_imu && (why = DivergenceReason(nodes, inertial, config.max_speed_mps))) {
    // The window's states are not trusted: its scans are dropped, not emitted as keyframes.
    warnings.push_back("LIO diverged (" + *why + "): re-initializing at " + StampText(input.end) + ", " +
                       std::to_string(window.size()) + " scans of the window dropped");
    Reset();
  }
  while (static_cast<int>(window.size()) > config.window_size) PopOldest();
  stats.solve_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  processed.push_back(stats);
}

// Registration of the newest scan (the window's last): ICP-style rounds that move only its nodes, then one
// solve of the whole window. A failed, non-finite or implausible result restores the guess (not in the map).
bool LidarOdometry::Impl::RegisterNewScan(ScanState& current) {
  const SavedStates saved = Save(nodes);
  const SE3 guess = NodePose(current.end_node);
  bool solved = true;
  // Re-query the planes after each solve until the new scan's begin and end poses move less than
  // kConvergedTranslation / kConvergedRotation in a round, or come back to where an earlier round left them
  // (the association then cycles through the same few plane sets: further rounds only repeat the cycle), or
  // association_rounds is reached.
  std::vector<std::pair<SE3, SE3>> visited;  // (begin, end) poses after each round
  auto near = [](const SE3& a, const SE3& b) {
    const SE3 step = a.inverse() * b;
    return step.translation().norm() < kConvergedTranslation && step.so3().angle() < kConvergedRotation;
  };
  visited.emplace_back(NodePose(current.begin_node), NodePose(current.end_node));
  for (int round = 0; round < config.association_rounds && solved; ++round) {
    Associate(current);
    solved = Solve(&stats.iterations, /*new_scan_only=*/true);
    const SE3 begin = NodePose(current.begin_node), end = NodePose(current.end_node);
    const bool repeated = std::any_of(visited.begin(), visited.end(), [&](const std::pair<SE3, SE3>& seen) {
      return near(seen.first, begin) && near(seen.second, end);
    });
    if (repeated) break;
    visited.emplace_back(begin, end);
  }
  if (solved && (config.window_size > 2 || inertial)) {
    LinkGnss();  // the new nodes are registered: a fair prediction for the integrity test
    Relinearize();
    solved = Solve(&stats.iterations);  // the whole window, once
  }
  stats.residuals = current.residuals;
  current.plane_cache = {};  // the map changes next
  const bool finite = AllFinite(nodes);
  const SE3 correction = guess.inverse() * (finite ? NodePose(current.end_node) : guess);
  if (solved && finite && correction.translation().norm() <= config.max_correction_m &&
      correction.so3().angle() <= config.max_correction_rad && current.residuals >= 6) {
    if (wheel) current.forward_sigma_m = ForwardSigma(current);
    return true;
  }
  Restore(saved, nodes);
  graph.Remove(FactorKind::kLidar, current.id);
  current.residuals = 0;
  warnings.push_back("lidar scan at " + StampText(current.stamp) +
                     ": registration rejected (solver failure, too few planes or implausible jump); kept the "
                     "predicted pose");
  return false;
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

Status LidarOdometry::AddWheel(const WheelSample& sample) {
  if (!impl_->wheel) return {};
  return impl_->AddWheel(sample);
}

Status LidarOdometry::AddGnss(const GnssFix& fix) {
  if (!impl_->gnss) return {};
  if (std::optional<std::string> skipped = impl_->gnss->Add(fix)) impl_->warnings.push_back(*skipped);
  return {};
}

Status LidarOdometry::AddImu(const ImuSample& sample) {
  if (!impl_->config.use_imu) return {};
  return impl_->AddImu(sample);
}

std::vector<Keyframe> LidarOdometry::TakeFinished() {
  std::vector<Keyframe> out = std::move(impl_->finished);
  impl_->finished.clear();
  return out;
}

std::vector<OdometryStats> LidarOdometry::TakeProcessedStats() {
  std::vector<OdometryStats> out = std::move(impl_->processed);
  impl_->processed.clear();
  return out;
}

void LidarOdometry::Finish() {
  Impl& w = *impl_;
  w.ProcessReady(/*flush=*/true);
  if (w.window.size() >= 2) {
    w.LinkGnss();
    const SavedStates saved = Save(w.nodes);
    int iterations = 0;
    w.Relinearize();
    if (!w.Solve(&iterations) || !AllFinite(w.nodes)) {
      Restore(saved, w.nodes);
      w.warnings.push_back("final window solve failed; kept the previous estimate");
    }
  }
  w.config.marginalize = false;  // nothing is solved after this: no prior needed
  while (!w.window.empty()) w.PopOldest();
}

const std::vector<std::string>& LidarOdometry::warnings() const { return impl_->warnings; }
const OdometryStats& LidarOdometry::last_stats() const { return impl_->stats; }
bool LidarOdometry::inertial() const { return impl_->inertial; }
const std::string& LidarOdometry::initialization() const { return impl_->init_summary; }

SensorFactorStats LidarOdometry::sensor_factors() const {
  SensorFactorStats stats;
  if (impl_->wheel) impl_->wheel->Report(stats);
  if (impl_->gnss) impl_->gnss->Report(stats);
  return stats;
}

std::optional<Georeference> LidarOdometry::georeference() const {
  if (!impl_->gnss) return std::nullopt;
  return impl_->gnss->georeference();
}

}  // namespace uf::estimator
