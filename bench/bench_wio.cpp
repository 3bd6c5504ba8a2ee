// bench_wio: wheel-inertial odometry (WIO, uf::estimator::InertialOdometry) over a simulated folder (IMU and
// wheel streams; LiDAR, camera and GNSS are ignored): KITTI-style translational drift and ATE (SE3-aligned)
// against the folder's groundtruth.tum, the wheel scale, and the time per node (mean / p95 / max), with the
// machine's load average. Nothing is asserted. bench/bench_wio.sh makes the urban 60 s folder and runs it.
//   usage: bench_wio FOLDER [--out EST.tum]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/inertial_odometry/inertial_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"

int main(int argc, char** argv) {
  using namespace uf;
  using uf::bench::LoadAverage;
  using uf::bench::Percentile;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_wio FOLDER [--out EST.tum]\n");
    return 2;
  }
  const std::string folder = argv[1];
  std::string out;
  for (int i = 2; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--out") out = argv[i + 1];
  auto reader = OpenDataset(folder);
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.error().c_str());
    return 1;
  }
  estimator::InertialOdometryConfig config;
  for (const StreamInfo& stream : (*reader)->description().streams)
    if (stream.kind == SensorKind::kWheel && stream.T_body_sensor)
      config.T_body_wheel = *stream.T_body_sensor;
  auto wio = estimator::InertialOdometry::Create(config);
  if (!wio.ok()) {
    std::fprintf(stderr, "%s\n", wio.error().c_str());
    return 1;
  }
  std::printf("bench_wio: %s, load average before %s\n", folder.c_str(), LoadAverage().c_str());
  const auto start = std::chrono::steady_clock::now();
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* imu = std::get_if<ImuSample>(&m.data)) return wio->AddImu(*imu);
    if (const auto* wheel = std::get_if<WheelSample>(&m.data)) return wio->AddWheel(*wheel);
    return Status();
  });
  wio->Finish();
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!read.ok()) std::fprintf(stderr, "read: %s\n", read.message().c_str());
  Trajectory estimate;
  for (const Keyframe& k : wio->TakeFinished()) {
    estimate.stamps.push_back(k.stamp);
    estimate.poses.push_back(k.T_world_body);
  }
  std::vector<double> node_ms;
  for (const estimator::InertialOdometryStats& s : wio->TakeProcessedStats()) node_ms.push_back(s.solve_ms);
  double mean = 0;
  for (double ms : node_ms) mean += ms / static_cast<double>(std::max<std::size_t>(node_ms.size(), 1));
  if (!out.empty()) {
    if (Status s = WriteTumTrajectory(out, estimate); !s.ok())
      std::fprintf(stderr, "%s\n", s.message().c_str());
  }
  auto truth = ReadTrajectory(folder + "/groundtruth.tum");
  if (!truth.ok()) {
    std::fprintf(stderr, "%s\n", truth.error().c_str());
    return 1;
  }
  EvalOptions options;
  options.kitti_drift = true;
  auto result = Evaluate(*truth, estimate, options);
  if (!result.ok()) {
    std::fprintf(stderr, "evaluation: %s\n", result.error().c_str());
    return 1;
  }
  const KittiDrift drift = result->kitti_drift.value_or(KittiDrift{});
  const estimator::SensorFactorStats factors = wio->sensor_factors();
  std::printf("initialization: %s\n", wio->initialization().c_str());
  std::printf("keyframes %zu, warnings %zu, wheel factors %d (skipped %d), wheel scale %.4f\n",
              estimate.size(), wio->warnings().size(), factors.wheel.added, factors.wheel.skipped,
              factors.wheel_scale);
  std::printf("KITTI drift: %.3f %% translation, %.4f deg/100 m rotation (%zu segments)\n", drift.t_pct,
              drift.r_deg_per_100m, drift.segments);
  std::printf("ATE (SE3-aligned RMSE): %.3f m\n", result->ape.rmse);
  std::printf("time per node: mean %.2f ms, p95 %.2f ms, max %.2f ms over %zu nodes; total %.2f s\n", mean,
              Percentile(node_ms, 0.95), Percentile(node_ms, 1.0), node_ms.size(), total_s);
  std::printf("load average after %s\n", LoadAverage().c_str());
  return 0;
}
