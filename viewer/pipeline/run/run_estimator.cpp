#include "viewer/pipeline/run/run_estimator.h"

#include "odometry/estimator/inertial_odometry/inertial_odometry.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"

namespace uf::pipeline {
namespace {

// One RunEstimator over either window: their interfaces agree but for the scans (WIO reads none), the
// camera (the LiDAR window reads none) and the type of their per-step statistics.
template <typename Odometry>
class WindowEstimator final : public RunEstimator {
 public:
  WindowEstimator(Odometry odometry, std::string step)
      : odometry_(std::move(odometry)), step_(std::move(step)) {}

  Status AddScan(const LidarScan& scan) override {
    if constexpr (requires(Odometry & o) { o.AddScan(scan); })
      return odometry_.AddScan(scan);
    else
      return {};
  }
  Status AddImu(const ImuSample& sample) override { return odometry_.AddImu(sample); }
  Status AddWheel(const WheelSample& sample) override { return odometry_.AddWheel(sample); }
  Status AddGnss(const GnssFix& fix) override { return odometry_.AddGnss(fix); }
  Status AddCameraFrame(const CameraFrame& frame) override {
    if constexpr (requires(Odometry & o) { o.AddCameraFrame(frame); })
      return odometry_.AddCameraFrame(frame);
    else
      return {};
  }
  Status AddRightCameraFrame(const CameraFrame& frame) override {
    if constexpr (requires(Odometry & o) { o.AddRightCameraFrame(frame); })
      return odometry_.AddRightCameraFrame(frame);
    else
      return {};
  }
  std::vector<estimator::TrackedFrame> TakeTrackedFrames() override {
    if constexpr (requires(Odometry & o) { o.TakeTrackedFrames(); })
      return odometry_.TakeTrackedFrames();
    else
      return {};
  }
  std::vector<Keyframe> TakeFinished() override { return odometry_.TakeFinished(); }
  std::vector<StepTime> TakeStepTimes() override {
    std::vector<StepTime> times;
    for (const auto& stats : odometry_.TakeProcessedStats()) {
      StepTime& step = times.emplace_back();
      step.stamp = stats.stamp;
      step.ms = stats.solve_ms;
      if constexpr (requires { stats.landmarks; }) {
        step.landmarks = stats.landmarks;
        step.reprojection_px = stats.reprojection_px;
      }
      if constexpr (requires { stats.window_ms; })
        step.stages = StageTimes{stats.prepare_ms, stats.associate_ms, stats.register_ms,
                                 stats.window_ms,  stats.map_ms,       stats.marginalize_ms};
    }
    return times;
  }
  std::vector<estimator::TrackEvent> TakeEvents() override {
    if constexpr (requires(Odometry & o) { o.TakeEvents(); })
      return odometry_.TakeEvents();
    else
      return {};
  }
  Status SetLidarExtrinsic(const SE3& T_body_lidar) override {
    if constexpr (requires(Odometry & o) { o.SetLidarExtrinsic(T_body_lidar); })
      return odometry_.SetLidarExtrinsic(T_body_lidar);
    else
      return Status::Error("SetLidarExtrinsic: the " + step_ + " window reads no LiDAR");
  }
  void Finish() override { odometry_.Finish(); }

  const std::vector<std::string>& warnings() const override { return odometry_.warnings(); }
  const std::string& initialization() const override { return odometry_.initialization(); }
  estimator::SensorFactorStats sensor_factors() const override { return odometry_.sensor_factors(); }
  std::optional<Georeference> georeference() const override { return odometry_.georeference(); }
  std::string step() const override { return step_; }

 private:
  Odometry odometry_;
  std::string step_;
};

template <typename Odometry, typename Config>
Expected<std::unique_ptr<RunEstimator>> Make(const Config& config, const char* step) {
  Expected<Odometry> odometry = Odometry::Create(config);
  if (!odometry) return odometry.status();
  return std::unique_ptr<RunEstimator>(
      std::make_unique<WindowEstimator<Odometry>>(std::move(*odometry), step));
}

}  // namespace

Expected<std::unique_ptr<RunEstimator>> CreateRunEstimator(const EstimatorMode& mode,
                                                           const estimator::LidarOdometryConfig& lo,
                                                           const estimator::InertialOdometryConfig& wio) {
  if (mode.core == OdometryMode::kWio) return Make<estimator::InertialOdometry>(wio, "node");
  return Make<estimator::LidarOdometry>(lo, "scan");
}

}  // namespace uf::pipeline
