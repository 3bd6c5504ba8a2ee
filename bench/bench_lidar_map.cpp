// bench_lidar_map: per-scan cost of the LiDAR side of the estimator on the recorded KITTI 00 keyframes (80
// HDL-64 scans, ~120k points): voxel downsampling, map insertion (+ RemoveFarFrom), plane queries (each
// fits the plane of its 27-voxel block; on one thread, then on all threads) and point-to-plane factor
// evaluations with Jacobians. Scans are placed with the ground-truth poses, so the figures isolate the map
// from the registration. Figures are printed, not asserted.
//   usage: bench_lidar_map [KITTI_FOLDER] [--query-voxel M] [--map-voxel M]
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "odometry/estimator/factors/point_to_plane_factor.h"
#include "odometry/estimator/lidar/voxel_downsample.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/trajectory_file.h"

namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Figure {
  std::vector<double> values;
  void Add(double value) { values.push_back(value); }
  double Mean() const {
    double sum = 0;
    for (double v : values) sum += v;
    return values.empty() ? 0 : sum / values.size();
  }
  double Max() const { return values.empty() ? 0 : *std::max_element(values.begin(), values.end()); }
};

// The ground-truth pose nearest in time to `stamp`.
const uf::SE3& NearestPose(const uf::Trajectory& truth, uf::Stamp stamp) {
  const auto it = std::lower_bound(truth.stamps.begin(), truth.stamps.end(), stamp);
  std::size_t index = static_cast<std::size_t>(it - truth.stamps.begin());
  if (index == truth.size() || (index > 0 && stamp - truth.stamps[index - 1] < truth.stamps[index] - stamp))
    --index;
  return truth.poses[index];
}

}  // namespace

int main(int argc, char** argv) {
  std::string folder = std::string(UF_SOURCE_DIR) + "/../shared/data/kitti00-keyframes";
  double query_voxel = 1.0, map_voxel = 0.5;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--query-voxel" && i + 1 < argc) {
      query_voxel = std::atof(argv[++i]);
    } else if (arg == "--map-voxel" && i + 1 < argc) {
      map_voxel = std::atof(argv[++i]);
    } else if (!arg.empty() && arg[0] != '-') {
      folder = arg;
    } else {
      std::fprintf(stderr, "usage: bench_lidar_map [KITTI_FOLDER] [--query-voxel M] [--map-voxel M]\n");
      return 2;
    }
  }
  auto reader = uf::OpenDataset(folder);
  if (!reader.ok()) {
    std::fprintf(stderr, "bench_lidar_map: %s\n", reader.error().c_str());
    return 1;
  }
  const auto& gt_path = (*reader)->description().ground_truth;
  if (!gt_path) {
    std::fprintf(stderr, "bench_lidar_map: no ground truth beside %s\n", folder.c_str());
    return 1;
  }
  auto truth = uf::ReadTrajectory(gt_path->string());
  if (!truth.ok() || !truth->has_stamps()) {
    std::fprintf(stderr, "bench_lidar_map: ground truth: %s\n",
                 truth.ok() ? "no stamps" : truth.error().c_str());
    return 1;
  }

  uf::estimator::VoxelHashMap map;  // paper defaults: 0.5 m voxels, gate 0.12, 100 m range
  Figure downsample_map_ms, downsample_query_ms, insert_ms, query_ms, parallel_query_ms, factor_us;
  Figure raw_points, map_points_in, query_points, plane_fraction;
  std::size_t scans = 0;
  while (true) {
    auto next = (*reader)->Next();
    if (!next.ok()) {
      std::fprintf(stderr, "bench_lidar_map: %s\n", next.error().c_str());
      return 1;
    }
    if (!*next) break;
    const auto* scan = std::get_if<uf::LidarScan>(&(*next)->data);
    if (scan == nullptr) continue;
    const uf::SE3& T_world_lidar = NearestPose(*truth, scan->stamp + (scan->end - scan->stamp) / 2);
    raw_points.Add(static_cast<double>(scan->points.size()));

    auto start = Clock::now();
    const std::vector<uf::LidarPoint> map_cloud = uf::estimator::VoxelDownsample(scan->points, map_voxel);
    downsample_map_ms.Add(MillisecondsSince(start));
    start = Clock::now();
    const std::vector<uf::LidarPoint> query_cloud = uf::estimator::VoxelDownsample(scan->points, query_voxel);
    downsample_query_ms.Add(MillisecondsSince(start));
    map_points_in.Add(static_cast<double>(map_cloud.size()));
    query_points.Add(static_cast<double>(query_cloud.size()));

    std::vector<Eigen::Vector3d> query_world;
    query_world.reserve(query_cloud.size());
    for (const uf::LidarPoint& p : query_cloud)
      query_world.push_back(T_world_lidar * Eigen::Vector3d(p.x, p.y, p.z));
    if (scans > 0) {  // query this scan against the map of the previous ones, as the window would
      std::vector<std::pair<std::size_t, uf::estimator::Plane>> matches;
      start = Clock::now();
      for (std::size_t i = 0; i < query_world.size(); ++i)
        if (const auto plane = map.PlaneNear(query_world[i])) matches.emplace_back(i, *plane);
      query_ms.Add(MillisecondsSince(start));
      start = Clock::now();
      std::vector<char> has_plane(query_world.size(), 0);
      tbb::parallel_for(std::size_t{0}, query_world.size(),
                        [&](std::size_t i) { has_plane[i] = map.PlaneNear(query_world[i]).has_value(); });
      parallel_query_ms.Add(MillisecondsSince(start));
      const std::size_t found = std::count(has_plane.begin(), has_plane.end(), 1);
      plane_fraction.Add(static_cast<double>(found) / std::max<std::size_t>(1, query_world.size()));

      // Factor evaluations with both Jacobians (begin = end = the truth pose, a from the point's time).
      const auto pose = uf::estimator::PoseBlock(T_world_lidar);
      const double* blocks[2] = {pose.data(), pose.data()};
      double residual = 0, jacobian_b[7], jacobian_e[7];
      double* jacobians[2] = {jacobian_b, jacobian_e};
      const double sweep_ns = static_cast<double>(std::max<uf::Stamp>(1, scan->end - scan->stamp));
      std::vector<std::unique_ptr<uf::estimator::PointToPlaneFactor>> factors;
      factors.reserve(matches.size());
      for (const auto& [i, plane] : matches) {
        const uf::LidarPoint& p = query_cloud[i];
        factors.push_back(std::make_unique<uf::estimator::PointToPlaneFactor>(
            Eigen::Vector3d(p.x, p.y, p.z), std::clamp(p.offset_ns / sweep_ns, 0.0, 1.0), plane, uf::SE3()));
      }
      start = Clock::now();
      double checksum = 0;
      for (const auto& factor : factors) {
        factor->Evaluate(blocks, &residual, jacobians);
        checksum += residual + jacobian_b[0];
      }
      if (!factors.empty()) factor_us.Add(1000 * MillisecondsSince(start) / factors.size());
      if (checksum == 1e300) std::printf("?");  // keeps the loop
    }

    std::vector<Eigen::Vector3d> map_world;
    map_world.reserve(map_cloud.size());
    for (const uf::LidarPoint& p : map_cloud)
      map_world.push_back(T_world_lidar * Eigen::Vector3d(p.x, p.y, p.z));
    start = Clock::now();
    map.Insert(map_world);
    map.RemoveFarFrom(T_world_lidar.translation());
    insert_ms.Add(MillisecondsSince(start));
    ++scans;
  }

  std::printf("bench_lidar_map: %zu scans of %s (mean %.0f points)\n", scans, folder.c_str(),
              raw_points.Mean());
  std::printf("  per scan                          mean       max\n");
  std::printf("  downsample %.2f m (%5.0f pts) %8.2f ms %8.2f ms\n", map_voxel, map_points_in.Mean(),
              downsample_map_ms.Mean(), downsample_map_ms.Max());
  std::printf("  downsample %.2f m (%5.0f pts) %8.2f ms %8.2f ms\n", query_voxel, query_points.Mean(),
              downsample_query_ms.Mean(), downsample_query_ms.Max());
  std::printf("  insert + RemoveFarFrom         %8.2f ms %8.2f ms\n", insert_ms.Mean(), insert_ms.Max());
  std::printf("  PlaneNear, one thread          %8.2f ms %8.2f ms\n", query_ms.Mean(), query_ms.Max());
  std::printf("  PlaneNear, all threads (TBB)   %8.2f ms %8.2f ms\n", parallel_query_ms.Mean(),
              parallel_query_ms.Max());
  std::printf("  query points with a plane      %8.1f %%\n", 100 * plane_fraction.Mean());
  std::printf("  factor Evaluate + Jacobians    %8.3f us per residual\n", factor_us.Mean());
  std::printf("  map at the end: %zu voxels, %zu points\n", map.voxel_count(), map.point_count());
  return 0;
}
