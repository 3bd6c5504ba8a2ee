#include "odometry/estimator/lidar_odometry/lidar_odometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {
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
    // When the map's voxels nest in the registration voxels, the registration points are drawn from the (far
    // fewer) map points: a random point of a random occupied map voxel of each registration voxel, unrelated
    // to the acquisition order as a draw over all its points would be (DownsamplePrepared).
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

  // Nodes: the first sweep of a map gets a single node (StartMap); later sweeps a begin and an end node,
  // sharing the previous end node when they start where it ended.
  if (nodes.empty()) {
    StartMap(std::move(scan));
  } else {
    const bool share = std::llabs(input.stamp - nodes.back().stamp) < kSharedNodeTolerance;
    scan.begin_node = share ? LastNodeId() : AddNode(input.stamp);
    scan.end_node = input.end - NodeAt(scan.begin_node).stamp >= kSharedNodeTolerance ? AddNode(input.end)
                                                                                      : scan.begin_node;
    if (inertial && config.imu_deskew && scan.end_node != scan.begin_node) CorrectSweepByImu(scan);
    if (!config.use_imu && !share && scan.end_node != scan.begin_node) AddSweepVelocityPrior(scan);
    window.push_back(std::move(scan));
    if (RegisterNewScan(window.back())) {
      InsertIntoMap(window.back());
      RemapFirstSweep();
    } else if (consecutive_rejections >= config.max_rejected_scans) {
      Restart();
    }
    if (config.use_imu && !inertial) TryInitializeInertial();
  }
  if (std::optional<std::string> why;
      config.use_imu && (why = DivergenceReason(nodes, inertial, config.max_speed_mps))) {
    // The window's states are not trusted: its scans are dropped, not emitted as keyframes.
    const std::string what = "LIO diverged (" + *why + "): re-initializing at " + StampText(input.end) +
                             ", " + std::to_string(window.size()) + " scans of the window dropped";
    warnings.push_back(what);
    events.push_back({TrackEvent::Kind::kRestarted, input.stamp, what});
    Reset();
  }
  while (static_cast<int>(window.size()) > config.window_size) PopOldest();
  if (visual) {  // else both stay -1
    stats.landmarks = visual->landmarks_in_graph();
    stats.reprojection_px = visual->mean_reprojection_px();
  }
  stats.solve_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  processed.push_back(stats);
}

// The first scan of a (new) local map: nothing to register against, so it gets a single node at its middle:
// its motion is unknown, so it is mapped as if at rest, which is the pose at its middle to first order; two
// nodes would leave its end node without data.
void LidarOdometry::Impl::StartMap(ScanState scan) {
  scan.begin_node = scan.end_node = AddNode(scan.stamp + (scan.end - scan.stamp) / 2);
  window.push_back(std::move(scan));
  InsertIntoMap(window.back());
  last_registered = RegisteredPose{window.back().end, NodePose(window.back().end_node)};
  last_move_m = 0;
}

// Recovery after max_rejected_scans consecutive rejections (the map no longer matches what the LiDAR sees):
// the window's scans leave as keyframes (the rejected ones with their predicted pose and no points), and a
// new local map starts with the newest scan, at the last registered pose (in initialized LIO at the newest
// scan's IMU prediction, which carries the motion through the failure). The trajectory goes on from there;
// the event marks the discontinuity.
void LidarOdometry::Impl::Restart() {
  ScanState current = std::move(window.back());
  window.pop_back();
  const SE3 predicted = PoseAt(NodePose(current.begin_node), NodePose(current.end_node), 0.5);
  const bool imu_carries = inertial && predicted.matrix().allFinite();
  const SE3 anchor = imu_carries ? predicted : last_registered ? last_registered->pose : restart_pose;
  for (ScanState& scan : window) Release(scan);
  const int rejected = consecutive_rejections;
  Reset();
  restart_pose = anchor;
  current.plane_cache = {};
  current.residuals = current.visited = current.on_plane = 0;
  StartMap(std::move(current));
  events.push_back({TrackEvent::Kind::kRestarted, window.back().stamp,
                    "local map restarted after " + std::to_string(rejected) + " rejected scans, at " +
                        (imu_carries ? "the IMU prediction" : "the last registered pose") +
                        " (a discontinuity)"});
  warnings.push_back("lidar scan at " + StampText(window.back().stamp) + ": " + events.back().detail);
}

LidarOdometry::LidarOdometry(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LidarOdometry::LidarOdometry(LidarOdometry&&) noexcept = default;
LidarOdometry& LidarOdometry::operator=(LidarOdometry&&) noexcept = default;
LidarOdometry::~LidarOdometry() = default;

Expected<LidarOdometry> LidarOdometry::Create(const LidarOdometryConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return status;
  Expected<std::unique_ptr<VisualProvider>> visual = VisualProvider::CreateIf(
      config.use_camera, config.visual, config.camera.get(), config.T_body_camera, "lio");
  if (!visual) return visual.status();
  if (*visual)
    if (Status s = (*visual)->SetStereoIf(config.camera, config.T_body_camera, config.right_camera,
                                          config.T_body_right_camera, "lio");
        !s.ok())
      return s;
  return LidarOdometry(std::make_unique<Impl>(config, std::move(*visual)));
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

Status LidarOdometry::AddCameraFrame(const CameraFrame& frame) {
  if (impl_->visual)
    impl_->visual->AddFrame(frame.stamp, frame.image, impl_->tracked_frames, impl_->warnings);
  return {};
}

Status LidarOdometry::AddRightCameraFrame(const CameraFrame& frame) {
  if (impl_->visual) impl_->visual->AddRightFrame(frame.stamp, frame.image, impl_->warnings);
  return {};
}

std::vector<TrackedFrame> LidarOdometry::TakeTrackedFrames() {
  std::vector<TrackedFrame> out = std::move(impl_->tracked_frames);
  impl_->tracked_frames.clear();
  return out;
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

std::vector<TrackEvent> LidarOdometry::TakeEvents() {
  std::vector<TrackEvent> out = std::move(impl_->events);
  impl_->events.clear();
  return out;
}

std::string_view TrackEventName(TrackEvent::Kind kind) {
  switch (kind) {
    case TrackEvent::Kind::kRejected:
      return "rejected";
    case TrackEvent::Kind::kFallbackGuess:
      return "fallback guess";
    case TrackEvent::Kind::kRestarted:
      return "restarted";
  }
  return "?";
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
    w.LinkVisual();
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
  w.ReleaseHeld(SE3());  // never initialized: they stay in the LO frame
  w.ReleaseLeverHeld(/*all=*/true);
}

const std::vector<std::string>& LidarOdometry::warnings() const { return impl_->warnings; }
std::size_t LidarOdometry::map_point_count() const { return impl_->map.point_count(); }
const OdometryStats& LidarOdometry::last_stats() const { return impl_->stats; }
bool LidarOdometry::inertial() const { return impl_->inertial; }
const std::string& LidarOdometry::initialization() const { return impl_->init_summary; }

SensorFactorStats LidarOdometry::sensor_factors() const {
  SensorFactorStats stats;
  if (impl_->wheel) impl_->wheel->Report(stats);
  if (impl_->gnss) impl_->gnss->Report(stats);
  if (impl_->visual) impl_->visual->Report(stats);
  stats.lidar_plane_rings = impl_->map.min_plane_rings_in_use();
  stats.lidar_translations_to_wheel = impl_->scans_leaving_translations_to_wheel;
  if (impl_->EstimatesLidarTranslation()) {
    stats.lidar_extrinsic = impl_->config.T_body_lidar;
    stats.lidar_translation_free_solves = impl_->lever_free_solves;
    stats.lidar_translation_solves = impl_->lever_solves;
  }
  return stats;
}

std::optional<Georeference> LidarOdometry::georeference() const {
  if (!impl_->gnss) return std::nullopt;
  return impl_->gnss->georeference();
}

}  // namespace uf::estimator
