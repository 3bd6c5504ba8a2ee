// bench_long_run: LiDAR-inertial odometry (uf::estimator::LidarOdometry, LIO) over a long simulated folder
// with periodic LiDAR dropouts (the scans of the last --dropout-length seconds of every --dropout-every
// seconds are withheld), taking the highest resident memory of every 10 s of data: the peak RSS and its
// growth after the first 10 minutes, beside them the heap in use (glibc's main arena: RSS less the freed
// memory the allocator keeps for reuse and its fragmentation) and the local map's size, the real-time factor,
// the ATE (SE3-aligned) against the folder's groundtruth.tum, the number of non-finite poses and the tracking
// events. Writes rss_over_time.csv and rss_over_time.png to --out. Nothing is asserted.
// bench/bench_long_run.sh makes the 1-hour urban folder and runs it.
//   usage: bench_long_run FOLDER [--out DIR] [--dropout-every S] [--dropout-length S] [--duration S]
// With UF_MALLOC_STATS set in the environment it ends with glibc's malloc_stats (per arena, to stderr).
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/eval/series_plot.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/types/process_memory.h"
#include "odometry/types/segmented_vector.h"

namespace {

// The highest resident memory of this process since the last call (VmHWM, then reset through clear_refs),
// MiB, so that a peak between two samples counts; 0 where /proc cannot be read.
double PeakResidentMiBSinceLastCall() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0;
      status >> kib;
      std::ofstream("/proc/self/clear_refs") << "5";  // the peak starts again from the current RSS
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

// Bytes the allocator has handed out from its main arena and not had back, MiB: what RSS is made of, less
// the freed memory the allocator keeps for reuse (KeepFreedMemoryForReuse) and its fragmentation. The
// worker threads' arenas are not counted (malloc_stats shows them: ~1 MiB here).
double HeapInUseMiB() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
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

  // Kept as run keeps them (viewer/pipeline/stages/odometry_stage.cpp): a pose and the statistics per scan.
  SegmentedVector<Stamp> stamps;
  SegmentedVector<SE3> poses;
  SegmentedVector<estimator::OdometryStats> processed;
  std::vector<double> data_s, rss_mib, heap_mib, map_points;
  std::vector<estimator::TrackEvent> events;
  long scans = 0, withheld = 0, non_finite = 0;
  Stamp first = 0, last = 0;
  const auto take = [&] {
    for (Keyframe& k : odometry->TakeFinished()) {
      if (!k.T_world_body.matrix().allFinite()) ++non_finite;
      if (!stamps.empty() && k.stamp <= stamps.back()) continue;
      stamps.push_back(k.stamp);
      poses.push_back(k.T_world_body);
    }
    for (estimator::TrackEvent& e : odometry->TakeEvents()) events.push_back(std::move(e));
    for (estimator::OdometryStats& s : odometry->TakeProcessedStats()) processed.push_back(s);
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
        rss_mib.push_back(PeakResidentMiBSinceLastCall());
        heap_mib.push_back(HeapInUseMiB());
        map_points.push_back(static_cast<double>(odometry->map_point_count()));
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
  if (std::getenv("UF_MALLOC_STATS")) malloc_stats();  // per arena, to stderr
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Trajectory estimate{std::move(stamps).TakeVector(), std::move(poses).TakeVector()};

  double peak = 0, first_10_min = 0, after_peak = 0, heap_first_10_min = 0, heap_after_peak = 0;
  double map_before = 0, map_after = 0;  // the local map's largest point count before / after 10 min
  for (std::size_t i = 0; i < rss_mib.size(); ++i) {
    peak = std::max(peak, rss_mib[i]);
    if (data_s[i] <= 600) {
      first_10_min = std::max(first_10_min, rss_mib[i]);
      heap_first_10_min = std::max(heap_first_10_min, heap_mib[i]);
    }
    if (data_s[i] > 600) {
      after_peak = std::max(after_peak, rss_mib[i]);
      heap_after_peak = std::max(heap_after_peak, heap_mib[i]);
    }
    double& map_peak = data_s[i] <= 600 ? map_before : map_after;
    map_peak = std::max(map_peak, map_points[i]);
  }
  std::ofstream csv(out / "rss_over_time.csv");
  csv << "data_s,rss_mib,heap_in_use_mib,map_points\n";
  for (std::size_t i = 0; i < rss_mib.size(); ++i)
    csv << data_s[i] << "," << rss_mib[i] << "," << heap_mib[i] << "," << map_points[i] << "\n";
  if (!rss_mib.empty()) {
    // The growth allowed after the first 10 minutes: their peak plus 10 %.
    const std::optional<SeriesLevel> limit =
        after_peak > 0 ? std::optional<SeriesLevel>({1.1 * first_10_min, "first 10 min peak + 10 %"})
                       : std::nullopt;
    if (Status s = WriteSeriesPlot((out / "rss_over_time.png").string(), data_s, rss_mib,
                                   "peak RSS per 10 s of data", limit,
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
  if (after_peak > 0) {
    std::printf(
        "  RSS: peak %.1f MiB, highest in the first 10 min %.1f MiB, after them %.1f MiB (growth %+.1f %%)\n",
        peak, first_10_min, after_peak, 100 * (after_peak / first_10_min - 1));
    std::printf(
        "  heap in use: highest in the first 10 min %.1f MiB, after them %.1f MiB (growth %+.1f %%)\n",
        heap_first_10_min, heap_after_peak, 100 * (heap_after_peak / heap_first_10_min - 1));
    std::printf("  local map: largest %.0f points in the first 10 min, %.0f after\n", map_before, map_after);
  } else {
    std::printf("  RSS: peak %.1f MiB (the run is shorter than 10 min: no growth figure)\n", peak);
  }
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
