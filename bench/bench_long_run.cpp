// bench_long_run: LiDAR-inertial odometry (uf::estimator::LidarOdometry, LIO) over a long simulated folder
// with periodic LiDAR dropouts (the scans of the last --dropout-length seconds of every --dropout-every
// seconds are withheld), sampling the process's resident memory every 10 s of data: peak RSS, the growth
// after the first 10 minutes, the real-time factor, the ATE (SE3-aligned) against the folder's
// groundtruth.tum, the number of non-finite poses and the tracking events. Writes rss_over_time.csv and
// rss_over_time.png to --out. Nothing is asserted. bench/bench_long_run.sh makes the 1-hour urban folder and
// runs it.
//   usage: bench_long_run FOLDER [--out DIR] [--dropout-every S] [--dropout-length S] [--duration S]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/eval/plots.h"
#include "odometry/eval/statistics.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/types/process_memory.h"

namespace {

// VmRSS of this process, MiB (0 where /proc cannot be read).
double ResidentMiB() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmRSS:") {
      double kib = 0;
      status >> kib;
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace uf;
  KeepFreedMemoryForReuse();  // as the ultrafusion binary does
  if (argc < 2) {
    std::fprintf(
        stderr,
        "usage: bench_long_run FOLDER [--out DIR] [--dropout-every S] [--dropout-length S] [--duration S]\n");
    return 2;
  }
  const std::string folder = argv[1];
  std::filesystem::path out = ".";
  double every_s = 60, length_s = 2, duration_limit_s = 1e12;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--out") out = argv[i + 1];
    if (key == "--dropout-every") every_s = std::stod(argv[i + 1]);
    if (key == "--dropout-length") length_s = std::stod(argv[i + 1]);
    if (key == "--duration") duration_limit_s = std::stod(argv[i + 1]);
  }
  auto reader = OpenDataset(folder);
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.error().c_str());
    return 1;
  }
  estimator::LidarOdometryConfig config;
  config.use_imu = true;
  config.input_voxel_m = 0.5;  // configs/run-sim.yaml
  int lidar = -1, imu = -1;
  const auto& streams = (*reader)->description().streams;
  for (std::size_t i = 0; i < streams.size(); ++i) {
    if (streams[i].kind == SensorKind::kLidar && lidar < 0) {
      lidar = static_cast<int>(i);
      if (streams[i].T_body_sensor) config.T_body_lidar = *streams[i].T_body_sensor;
    }
    if (streams[i].kind == SensorKind::kImu && imu < 0) imu = static_cast<int>(i);
  }
  auto odometry = estimator::LidarOdometry::Create(config);
  if (!odometry.ok() || lidar < 0 || imu < 0) {
    std::fprintf(stderr, "bench_long_run: %s needs a LiDAR and an IMU stream\n", folder.c_str());
    return 1;
  }

  Trajectory estimate;
  std::vector<double> data_s, rss_mib;
  std::vector<estimator::TrackEvent> events;
  long scans = 0, withheld = 0, non_finite = 0;
  Stamp first = 0, last = 0;
  const auto take = [&] {
    for (Keyframe& k : odometry->TakeFinished()) {
      if (!k.T_world_body.matrix().allFinite()) ++non_finite;
      if (!estimate.stamps.empty() && k.stamp <= estimate.stamps.back()) continue;
      estimate.stamps.push_back(k.stamp);
      estimate.poses.push_back(k.T_world_body);
    }
    for (estimator::TrackEvent& e : odometry->TakeEvents()) events.push_back(std::move(e));
  };
  const auto start = std::chrono::steady_clock::now();
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == lidar) {
      if (scans++ == 0) first = scan->stamp;
      last = scan->stamp;
      const double t = ToSeconds(scan->stamp - first);
      if (t > duration_limit_s) return Status();
      if (std::fmod(t, every_s) >= every_s - length_s) {
        ++withheld;
        return Status();
      }
      if (Status s = odometry->AddScan(*scan); !s.ok()) return s;
      if (data_s.empty() || t - data_s.back() >= 10) {
        data_s.push_back(t);
        rss_mib.push_back(ResidentMiB());
      }
    } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == imu) {
      if (scans > 0 && ToSeconds(sample->stamp - first) > duration_limit_s) return Status();
      if (Status s = odometry->AddImu(*sample); !s.ok()) return s;
    } else {
      return Status();
    }
    take();
    return Status();
  });
  if (!read.ok()) {
    std::fprintf(stderr, "%s\n", read.message().c_str());
    return 1;
  }
  odometry->Finish();
  take();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  double peak = 0, at_10_min = 0, after_peak = 0;
  for (std::size_t i = 0; i < rss_mib.size(); ++i) {
    peak = std::max(peak, rss_mib[i]);
    if (data_s[i] <= 600) at_10_min = rss_mib[i];
    if (data_s[i] > 600) after_peak = std::max(after_peak, rss_mib[i]);
  }
  std::ofstream csv(out / "rss_over_time.csv");
  csv << "data_s,rss_mib\n";
  for (std::size_t i = 0; i < rss_mib.size(); ++i) csv << data_s[i] << "," << rss_mib[i] << "\n";
  if (!rss_mib.empty()) {
    if (Status s =
            WriteErrorPlot((out / "rss_over_time.png").string(), data_s, rss_mib, ComputeStats(rss_mib),
                           "Resident memory of LIO over a long run", "data time [s]", "RSS [MiB]");
        !s.ok())
      std::fprintf(stderr, "%s\n", s.message().c_str());
  }
  int rejected = 0, restarts = 0;
  for (const estimator::TrackEvent& e : events) {
    rejected += e.kind == estimator::TrackEvent::Kind::kRejected;
    restarts += e.kind == estimator::TrackEvent::Kind::kRestarted;
    if (e.kind != estimator::TrackEvent::Kind::kFallbackGuess)
      std::printf("  %s at %.1f s: %s\n", std::string(estimator::TrackEventName(e.kind)).c_str(),
                  ToSeconds(e.stamp - first), e.detail.c_str());
  }
  const double duration_s = std::min(ToSeconds(last - first), duration_limit_s);
  std::printf("bench_long_run: %s, %.0f s of data, %ld scans read (%ld withheld: %.1f s every %.0f s)\n",
              folder.c_str(), duration_s, scans, withheld, length_s, every_s);
  if (after_peak > 0)
    std::printf("  RSS: peak %.1f MiB, at 10 min %.1f MiB, largest after 10 min %.1f MiB (growth %+.1f %%)\n",
                peak, at_10_min, after_peak, 100 * (after_peak / at_10_min - 1));
  else
    std::printf("  RSS: peak %.1f MiB (the run is shorter than 10 min: no growth figure)\n", peak);
  std::printf("  wall %.0f s, real-time factor %.2f (data time / wall time)\n", wall_s, duration_s / wall_s);
  std::printf("  poses %zu, non-finite %ld, rejected scans %d, restarts %d, warnings %zu\n", estimate.size(),
              non_finite, rejected, restarts, odometry->warnings().size());
  if (const auto& truth_path = (*reader)->description().ground_truth) {
    auto truth = ReadTrajectory(truth_path->string());
    if (truth.ok()) {
      auto result = Evaluate(*truth, estimate, EvalOptions{});
      if (result.ok())
        std::printf("  ATE (SE3-aligned) rmse %.3f m over %zu poses\n", result->ape.rmse, estimate.size());
    }
  }
  std::printf("  machine load average (1/5/15 min): %s on %u cores\n", bench::LoadAverage().c_str(),
              std::thread::hardware_concurrency());
  return 0;
}
