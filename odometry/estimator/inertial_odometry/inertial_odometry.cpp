#include "odometry/estimator/inertial_odometry/inertial_odometry.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "odometry/estimator/inertial_odometry/inertial_window.h"

namespace uf::estimator {

// Nodes on the grid of IMU time (with the camera: at the frames' node stamps), each once the IMU covers it
// and the wheel does too, or once the IMU is wheel_max_wait_s past it (the wheel stalled), or at the end of
// the data (flush). The nodes start where the streams have begun, so that they cover the first node.
void InertialOdometry::Impl::ProcessReady(bool flush) {
  if (!next_stamp) {
    const bool wheel_started = wheel.CoveredUntil() != std::numeric_limits<Stamp>::min();
    if (imu.empty() || (config.use_wheel && !wheel_started)) return;
    next_stamp = config.use_wheel ? std::max(imu.CoveredUntil(), wheel.CoveredUntil()) : imu.CoveredUntil();
  }
  for (std::optional<Stamp> stamp = NextNodeStamp(); stamp && imu.CoveredUntil() >= *stamp;
       stamp = NextNodeStamp()) {
    if (config.use_wheel) {
      const bool wheel_covers = wheel.CoveredUntil() >= *stamp;
      const bool stalled = imu.CoveredUntil() - *stamp > FromSeconds(config.wheel_max_wait_s);
      if (!wheel_covers && !stalled && !flush) return;
    }
    next_stamp = visual ? *stamp + 1 : *stamp + FromSeconds(config.node_interval_s);
    AddNodeAt(*stamp);
  }
}

std::optional<Stamp> InertialOdometry::Impl::NextNodeStamp() const {
  if (!visual) return next_stamp;
  return visual->NextNodeStamp(*next_stamp);
}

void InertialOdometry::Impl::AttachProviders() {
  wheel.Attach(graph);
  if (visual) visual->Attach(graph);
}

// One node, as the method reads: before initialization it only waits in the initialization window; then
// the IMU predicts it from the last node, the IMU and wheel factors link the two, the window is solved, and
// the oldest node leaves when the window is full. An IMU gap ends the window (its nodes are final) and
// starts a new initialization with this node.
void InertialOdometry::Impl::AddNodeAt(Stamp stamp) {
  if (!inertial) {
    init_stamps.push_back(stamp);
    TryInitialize();
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  InertialOdometryStats stats;
  stats.stamp = stamp;
  const WindowNode& last = nodes.back();
  Expected<ImuPreintegration> pre = imu.Preintegrate(last.stamp, stamp, last.speed_bias.data());
  if (!pre) {
    warnings.push_back("IMU at " + StampText(stamp) + ": " + pre.status().message() +
                       "; the window ends there and WIO initializes again");
    Restart(/*keep_window=*/true);
    init_stamps.push_back(stamp);
    return;
  }
  const NavState predicted = pre->Predict(NodeNavState(last));
  WindowNode node;
  node.stamp = stamp;
  node.pose = PoseBlock(predicted.T_world_imu);
  node.speed_bias = SpeedBiasBlock(predicted);
  LinkNode(PushNode(node), std::move(*pre));
  SolveAndSlide(stats);
  stats.solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  processed.push_back(stats);
}

// Solves the window; a failed solve keeps the prediction, a diverged window is dropped and initializes
// again; then the oldest nodes leave while the window is over its size.
void InertialOdometry::Impl::SolveAndSlide(InertialOdometryStats& stats) {
  const SavedStates saved = Save(nodes);
  if (!Solve(&stats.iterations, &stats.outliers)) {
    Restore(saved, nodes);
    warnings.push_back("WIO solve at " + StampText(nodes.back().stamp) + " failed; kept the prediction");
  }
  if (std::optional<std::string> why = DivergenceReason(nodes, true, config.max_speed_mps)) {
    warnings.push_back("WIO diverged (" + *why + "): re-initializing at " + StampText(nodes.back().stamp) +
                       ", " + std::to_string(nodes.size()) + " nodes of the window dropped");
    Restart(/*keep_window=*/false);
    return;
  }
  while (static_cast<int>(nodes.size()) > config.window_size) MarginalizeOldest(&stats.marginalize_ms);
  if (visual) {  // else both stay -1
    stats.landmarks = visual->landmarks_in_graph();
    stats.reprojection_px = visual->mean_reprojection_px();
  }
}

// Drops the IMU and wheel samples that neither the window nor a waiting initialization needs.
void InertialOdometry::Impl::TrimStreams() {
  Stamp oldest = std::numeric_limits<Stamp>::max();
  if (!nodes.empty()) oldest = nodes.front().stamp;
  if (!init_stamps.empty()) oldest = std::min(oldest, init_stamps.front());
  if (restart_stamp) oldest = std::min(oldest, *restart_stamp);
  if (oldest == std::numeric_limits<Stamp>::max()) return;
  imu.Trim(oldest);
  wheel.Trim(oldest);
  if (visual) visual->Trim(oldest);
}

InertialOdometry::InertialOdometry(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
InertialOdometry::InertialOdometry(InertialOdometry&&) noexcept = default;
InertialOdometry& InertialOdometry::operator=(InertialOdometry&&) noexcept = default;
InertialOdometry::~InertialOdometry() = default;

Expected<InertialOdometry> InertialOdometry::Create(const InertialOdometryConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return status;
  Expected<std::unique_ptr<VisualProvider>> visual = VisualProvider::CreateIf(
      config.use_camera, config.visual, config.camera.get(), config.T_body_camera, "wio");
  if (!visual) return visual.status();
  if (*visual)
    if (Status s = (*visual)->SetStereoIf(config.camera, config.T_body_camera, config.right_camera,
                                          config.T_body_right_camera, "wio");
        !s.ok())
      return s;
  return InertialOdometry(std::make_unique<Impl>(config, std::move(*visual)));
}

Status InertialOdometry::AddImu(const ImuSample& sample) {
  if (std::optional<std::string> skipped = impl_->imu.Add(sample)) {
    impl_->warnings.push_back(*skipped);
    return {};
  }
  impl_->ProcessReady(/*flush=*/false);
  return {};
}

Status InertialOdometry::AddWheel(const WheelSample& sample) {
  if (std::optional<std::string> skipped = impl_->wheel.Add(sample)) {
    impl_->warnings.push_back(*skipped);
    return {};
  }
  impl_->ProcessReady(/*flush=*/false);
  return {};
}

Status InertialOdometry::AddCameraFrame(const CameraFrame& frame) {
  if (impl_->visual &&
      impl_->visual->AddFrame(frame.stamp, frame.image, impl_->tracked_frames, impl_->warnings))
    impl_->ProcessReady(/*flush=*/false);
  return {};
}

Status InertialOdometry::AddRightCameraFrame(const CameraFrame& frame) {
  if (!impl_->visual) return {};
  impl_->visual->AddRightFrame(frame.stamp, frame.image, impl_->warnings);
  impl_->ProcessReady(/*flush=*/false);  // the pair's left frame may now have its node
  return {};
}

std::vector<TrackedFrame> InertialOdometry::TakeTrackedFrames() {
  std::vector<TrackedFrame> out = std::move(impl_->tracked_frames);
  impl_->tracked_frames.clear();
  return out;
}

std::vector<Keyframe> InertialOdometry::TakeFinished() {
  std::vector<Keyframe> out = std::move(impl_->finished);
  impl_->finished.clear();
  return out;
}

std::vector<InertialOdometryStats> InertialOdometry::TakeProcessedStats() {
  std::vector<InertialOdometryStats> out = std::move(impl_->processed);
  impl_->processed.clear();
  return out;
}

void InertialOdometry::Finish() {
  Impl& w = *impl_;
  w.ProcessReady(/*flush=*/true);
  if (w.inertial) {
    // Every node is final (solved when it was added); the GNSS alignment stays as it is.
    while (!w.nodes.empty()) w.ReleaseOldest();
    w.graph.Clear();  // nothing is solved after the end of the data
  } else if (!w.init_stamps.empty()) {
    w.warnings.push_back("WIO ended before initializing: " + std::to_string(w.init_stamps.size()) +
                         " nodes waited (" + (w.last_init_failure.empty() ? "too few" : w.last_init_failure) +
                         ")");
  }
}

const std::vector<std::string>& InertialOdometry::warnings() const { return impl_->warnings; }
bool InertialOdometry::inertial() const { return impl_->inertial; }
const std::string& InertialOdometry::initialization() const { return impl_->init_summary; }

SensorFactorStats InertialOdometry::sensor_factors() const {
  SensorFactorStats stats;
  impl_->wheel.Report(stats);
  if (impl_->gnss) impl_->gnss->Report(stats);
  if (impl_->visual) impl_->visual->Report(stats);
  return stats;
}

Status InertialOdometry::AddGnss(const GnssFix& fix) {
  if (!impl_->gnss) return {};
  if (std::optional<std::string> skipped = impl_->gnss->Add(fix)) impl_->warnings.push_back(*skipped);
  return {};
}

std::optional<Georeference> InertialOdometry::georeference() const {
  if (!impl_->gnss) return std::nullopt;
  return impl_->gnss->georeference();
}

}  // namespace uf::estimator
