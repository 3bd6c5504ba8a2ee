// bench_lidar_odometry: LiDAR-only odometry (LO mode, uf::estimator::LidarOdometry) on the recorded KITTI 00
// keyframes (80 HDL-64 scans ~2 m apart): ATE (SE3-aligned, as `ultrafusion eval --align se3`), RPE (1 frame)
// and time per scan (mean / median / p95 / max; wall and process CPU time), with the machine's load average.
// Nothing is asserted.
//   usage: bench_lidar_odometry [KITTI_FOLDER] [--window N] [--input-voxel M] [--residuals N]
//          [--iterations N] [--condensed-rounds N] [--rounds N] [--acc A] [--ang W] [--sweep-acc S]
//          [--huber M] [--map-insert-voxel M] [--neighbour-weight W]
//          [--no-deskew] [--out EST.tum]
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/types/process_memory.h"

namespace {

// CPU time of the whole process (all threads), ms: less disturbed than wall time on a shared machine.
double ProcessCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  uf::KeepFreedMemoryForReuse();  // as the ultrafusion binary does
  std::string folder = std::string(UF_SOURCE_DIR) + "/../shared/data/kitti00-keyframes", out_path;
  uf::estimator::LidarOdometryConfig config;
  bool no_deskew = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--window" && has_value)
      config.window_size = std::atoi(argv[++i]);
    else if (arg == "--input-voxel" && has_value)
      config.input_voxel_m = std::atof(argv[++i]);
    else if (arg == "--residuals" && has_value)
      config.max_residuals_per_scan = std::atoi(argv[++i]);
    else if (arg == "--iterations" && has_value)
      config.max_iterations = std::atoi(argv[++i]);
    else if (arg == "--condensed-rounds" && has_value)
      config.condensed_lidar_rounds = std::atoi(argv[++i]);
    else if (arg == "--rounds" && has_value)
      config.association_rounds = std::atoi(argv[++i]);
    else if (arg == "--acc" && has_value)
      config.motion.acc_density = std::atof(argv[++i]);
    else if (arg == "--ang" && has_value)
      config.motion.angular_acc_density = std::atof(argv[++i]);
    else if (arg == "--sweep-acc" && has_value)
      config.motion.sweep_acc_density = std::atof(argv[++i]);
    else if (arg == "--huber" && has_value)
      config.huber_m = std::atof(argv[++i]);
    else if (arg == "--map-insert-voxel" && has_value)
      config.map_insert_voxel_m = std::atof(argv[++i]);
    else if (arg == "--neighbour-weight" && has_value)
      config.map.neighbour_weight = std::atof(argv[++i]);
    else if (arg == "--solver-time" && has_value)
      config.max_solver_time_s = std::atof(argv[++i]);
    else if (arg == "--gate" && has_value)
      config.max_plane_distance_m = std::atof(argv[++i]);
    else if (arg == "--no-deskew")
      no_deskew = true;
    else if (arg == "--out" && has_value)
      out_path = argv[++i];
    else if (!arg.empty() && arg[0] != '-')
      folder = arg;
    else {
      std::fprintf(stderr, "bench_lidar_odometry: unknown argument %s\n", arg.c_str());
      return 2;
    }
  }
  auto reader = uf::OpenDataset(folder);
  if (!reader.ok()) {
    std::fprintf(stderr, "bench_lidar_odometry: %s\n", reader.error().c_str());
    return 1;
  }
  const auto& gt_path = (*reader)->description().ground_truth;
  if (!gt_path) {
    std::fprintf(stderr, "bench_lidar_odometry: no ground truth beside %s\n", folder.c_str());
    return 1;
  }
  auto truth = uf::ReadTrajectory(gt_path->string());
  if (!truth.ok()) {
    std::fprintf(stderr, "bench_lidar_odometry: ground truth: %s\n", truth.error().c_str());
    return 1;
  }
  auto odometry = uf::estimator::LidarOdometry::Create(config);
  if (!odometry.ok()) {
    std::fprintf(stderr, "bench_lidar_odometry: %s\n", odometry.error().c_str());
    return 1;
  }
  std::vector<uf::LidarScan> scans;  // read first so that reading does not count in the timing
  const uf::Status read = uf::ForEachMeasurement(**reader, [&](uf::Measurement& m) {
    if (auto* scan = std::get_if<uf::LidarScan>(&m.data)) {
      if (no_deskew) scan->has_point_times = false;
      scans.push_back(std::move(*scan));
    }
    return uf::Status();
  });
  if (!read.ok()) {
    std::fprintf(stderr, "bench_lidar_odometry: %s\n", read.message().c_str());
    return 1;
  }
  std::vector<double> ms, cpu_ms;
  std::vector<uf::Keyframe> keyframes;
  std::size_t residuals = 0, iterations = 0;
  uf::estimator::OdometryStats stages;  // summed per-stage times
  for (const uf::LidarScan& scan : scans) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = ProcessCpuMs();
    if (uf::Status s = odometry->AddScan(scan); !s.ok()) {
      std::fprintf(stderr, "bench_lidar_odometry: %s\n", s.message().c_str());
      return 1;
    }
    auto done = odometry->TakeFinished();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    cpu_ms.push_back(ProcessCpuMs() - cpu_start);
    residuals += odometry->last_stats().residuals;
    iterations += odometry->last_stats().iterations;
    for (const uf::estimator::OdometryStats& st : odometry->TakeProcessedStats()) {
      stages.prepare_ms += st.prepare_ms;
      stages.associate_ms += st.associate_ms;
      stages.register_ms += st.register_ms;
      stages.window_ms += st.window_ms;
      stages.map_ms += st.map_ms;
      stages.marginalize_ms += st.marginalize_ms;
    }
    for (auto& k : done) keyframes.push_back(std::move(k));
  }
  odometry->Finish();
  for (auto& k : odometry->TakeFinished()) keyframes.push_back(std::move(k));
  for (const std::string& w : odometry->warnings()) std::printf("  warning: %s\n", w.c_str());

  uf::Trajectory estimate;
  for (const uf::Keyframe& k : keyframes) {
    estimate.stamps.push_back(k.stamp);
    estimate.poses.push_back(k.T_world_body);
  }
  if (!out_path.empty()) {
    std::ofstream out(out_path);
    for (const uf::Keyframe& k : keyframes) {
      const auto q = k.T_world_body.so3().quaternion();
      const auto& t = k.T_world_body.translation();
      out << std::fixed << uf::ToSeconds(k.stamp) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' '
          << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
  }
  uf::EvalOptions options;  // SE3 alignment, RPE over 1 frame
  auto result = uf::Evaluate(*truth, estimate, options);
  if (!result.ok()) {
    std::fprintf(stderr, "bench_lidar_odometry: eval: %s\n", result.error().c_str());
    return 1;
  }
  double mean = 0;
  for (double v : ms) mean += v;
  mean /= std::max<std::size_t>(1, ms.size());
  std::printf("bench_lidar_odometry: %zu scans of %s, %zu keyframes matched\n", scans.size(), folder.c_str(),
              result->ape_errors.size());
  std::printf("  config: window %d, input voxel %.2f m, residuals <= %d, LM iterations %d, rounds %d\n",
              config.window_size, config.input_voxel_m, config.max_residuals_per_scan, config.max_iterations,
              config.association_rounds);
  std::printf("  ATE (SE3-aligned) rmse %.3f m, mean %.3f m, max %.3f m\n", result->ape.rmse,
              result->ape.mean, result->ape.max);
  const auto worst = std::max_element(result->ape_errors.begin(), result->ape_errors.end());
  if (worst != result->ape_errors.end())
    std::printf("  worst APE at keyframe %zu of %zu\n",
                static_cast<std::size_t>(worst - result->ape_errors.begin()), result->ape_errors.size());
  if (result->rpe)
    std::printf("  RPE (1 frame)     rmse %.3f m, mean %.3f m, max %.3f m\n", result->rpe->rmse,
                result->rpe->mean, result->rpe->max);
  std::printf(
      "  time per scan: mean %.1f ms, median %.1f ms, p95 %.1f ms, max %.1f ms (mean residuals %.0f, LM "
      "iterations %.1f)\n",
      mean, uf::bench::Percentile(ms, 0.5), uf::bench::Percentile(ms, 0.95), uf::bench::Percentile(ms, 1.0),
      static_cast<double>(residuals) / std::max<std::size_t>(1, scans.size()),
      static_cast<double>(iterations) / std::max<std::size_t>(1, scans.size()));
  double cpu_mean = 0;
  for (double v : cpu_ms) cpu_mean += v;
  cpu_mean /= std::max<std::size_t>(1, cpu_ms.size());
  std::printf("  CPU time per scan (all threads): mean %.1f ms, median %.1f ms, p95 %.1f ms\n", cpu_mean,
              uf::bench::Percentile(cpu_ms, 0.5), uf::bench::Percentile(cpu_ms, 0.95));
  const double n = static_cast<double>(std::max<std::size_t>(1, scans.size()));
  std::printf(
      "  per scan by stage: prepare %.1f ms, associate %.1f ms, register solves %.1f ms, window solve %.1f "
      "ms, "
      "map %.1f ms, marginalize %.1f ms\n",
      stages.prepare_ms / n, stages.associate_ms / n, stages.register_ms / n, stages.window_ms / n,
      stages.map_ms / n, stages.marginalize_ms / n);
  std::printf("  machine load average (1/5/15 min): %s on 2 cores\n", uf::bench::LoadAverage().c_str());
  return 0;
}
