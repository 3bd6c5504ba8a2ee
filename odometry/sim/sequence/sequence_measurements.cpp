#include "odometry/sim/sequence/sequence_measurements.h"

#include <algorithm>
#include <cmath>

#include "odometry/io/image_decode.h"

namespace uf::sim {
namespace {

// Independent seeds per sensor from one user seed (splitmix64 finaliser).
std::uint64_t SubSeed(std::uint64_t seed, std::uint64_t sensor) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (sensor + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

Expected<Simulators> MakeSimulators(const SimulationConfig& config, const SimulationTrajectory& motion,
                                    const RayCaster& caster) {
  Simulators s;
  const auto& spline = motion.spline;
  if (config.imu.enabled) {
    auto imu =
        ImuSimulator::Create(spline, SE3(), config.imu.rate_hz, config.imu.noise, SubSeed(config.seed, 0));
    if (!imu) return Status::Error("sim.imu: " + imu.error());
    auto generated = imu->Generate(motion.begin, motion.end);
    if (!generated) return generated.status();
    s.imu = std::move(*generated);
  }
  if (config.lidar.enabled) {
    LidarConfig lidar = config.lidar.model;
    lidar.threads = config.threads;
    auto simulator = LidarSimulator::Create(lidar, caster, spline, config.lidar.placement.T_body_sensor,
                                            SubSeed(config.seed, 1));
    if (!simulator) return simulator.status();
    s.lidar = std::move(*simulator);
  }
  if (config.camera.enabled) {
    CameraConfig camera = config.camera.model;
    camera.threads = config.threads;
    auto renderer = CameraRenderer::Create(camera, caster, spline, config.camera.placement.T_body_sensor,
                                           SubSeed(config.seed, 2));
    if (!renderer) return renderer.status();
    s.camera = std::move(*renderer);
    if (config.camera.stereo_baseline_m > 0.0) {
      auto right = CameraRenderer::Create(
          camera, caster, spline, RightCameraPlacement(config.camera).T_body_sensor, SubSeed(config.seed, 5));
      if (!right) return right.status();
      s.right_camera = std::move(*right);
    }
  }
  if (config.wheel.enabled) {
    auto wheel = WheelSimulator::Create(spline, config.wheel.placement.T_body_sensor, config.wheel.model,
                                        SubSeed(config.seed, 3));
    if (!wheel) return wheel.status();
    auto generated = wheel->Generate(motion.begin, motion.end);
    if (!generated) return generated.status();
    s.wheel = std::move(generated->samples);
  }
  if (config.gnss.enabled) {
    auto gnss = GnssSimulator::Create(spline, config.gnss.placement.T_body_sensor, config.gnss.model,
                                      config.origin, SubSeed(config.seed, 4));
    if (!gnss) return gnss.status();
    auto generated = gnss->Generate(motion.begin, motion.end);
    if (!generated) return generated.status();
    s.gnss = std::move(generated->fixes);
  }
  return s;
}

std::vector<Stamp> WrittenSweepStarts(Stamp begin, Stamp end, Stamp period, double rate_hz,
                                      double keyframe_rate_hz) {
  std::vector<Stamp> starts;
  const double sweeps_per_scan = keyframe_rate_hz > 0.0 ? rate_hz / keyframe_rate_hz : 1.0;
  for (std::int64_t k = 0;; ++k) {
    const std::int64_t j = std::llround(static_cast<double>(k) * sweeps_per_scan);
    const Stamp t = begin + j * period;
    if (t + period > end) break;
    starts.push_back(t);
  }
  return starts;
}

std::vector<Event> Schedule(const std::vector<SequenceStream>& streams, const Simulators& s,
                            const SimulationTrajectory& motion) {
  std::vector<Event> events;
  for (int i = 0; i < static_cast<int>(streams.size()); ++i) {
    const Stamp delay = streams[i].stamp_delay;
    auto add = [&](Stamp t, std::size_t index) { events.push_back({t + delay, i, t, index}); };
    switch (streams[i].kind) {
      case SensorKind::kImu:
        for (std::size_t k = 0; k < s.imu->samples.size(); ++k) add(s.imu->samples[k].stamp, k);
        break;
      case SensorKind::kWheel:
        for (std::size_t k = 0; k < s.wheel.size(); ++k) add(s.wheel[k].stamp, k);
        break;
      case SensorKind::kGnss:
        for (std::size_t k = 0; k < s.gnss.size(); ++k) add(s.gnss[k].stamp, k);
        break;
      case SensorKind::kLidar:
        for (Stamp t : WrittenSweepStarts(motion.begin, motion.end, s.lidar->period(),
                                          s.lidar->config().rate_hz, streams[i].keyframe_rate_hz))
          add(t, 0);
        break;
      case SensorKind::kCamera: {
        const double period_ns = 1e9 / streams[i].rate_hz;
        for (std::int64_t k = 0;; ++k) {
          const Stamp t = motion.begin + std::llround(static_cast<double>(k) * period_ns);
          if (t > motion.end) break;
          add(t, 0);
        }
        break;
      }
    }
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const Event& a, const Event& b) { return a.stamp < b.stamp; });
  return events;
}

Expected<MeasurementData> Produce(const Event& event, const SequenceStream& stream, const Simulators& s) {
  MeasurementData data;
  switch (stream.kind) {
    case SensorKind::kImu:
      data = s.imu->samples[event.index];
      break;
    case SensorKind::kWheel:
      data = s.wheel[event.index];
      break;
    case SensorKind::kGnss:
      data = s.gnss[event.index];
      break;
    case SensorKind::kLidar: {
      auto scan = s.lidar->Scan(event.true_time);
      if (!scan) return scan.status();
      data = std::move(*scan);
      break;
    }
    case SensorKind::kCamera: {
      const CameraRenderer& renderer = stream.camera == 1 ? *s.right_camera : *s.camera;
      auto frame = renderer.Render(event.true_time, stream.camera);
      if (!frame) return frame.status();
      auto png = EncodePng(frame->image, stream.name + " frame at " + FormatSeconds(event.true_time));
      if (!png) return png.status();
      frame->encoded.format = "png";
      frame->encoded.bytes = std::move(*png);
      frame->image = Image{};
      data = std::move(*frame);
      break;
    }
  }
  ShiftStamp(data, stream.stamp_delay);
  return data;
}

}  // namespace uf::sim
