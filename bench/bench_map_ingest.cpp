// Benchmark of the global map (target: ingest >= 2 M points/s): 100 synthetic spinning-LiDAR scans of
// 120k points (32 rings x 3750 columns) of a street (ground plane and two facades 8 m to either side),
// taken 1 m apart along the street with 2 cm range noise and a colour on every point, inserted into a 5 cm
// map. Prints ingest rate, voxels, memory, then the time to stream the MapView (with and without normals),
// and to save and load map.vdb.
//
//   bench_map_ingest [scans (100)] [voxel_size_m (0.05)]
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <vector>

#include "mapping/global_map.h"
#include "mapping/map_file.h"
#include "mapping/map_view.h"

namespace {

using uf::mapping::PointColor;

struct Scan {
  std::vector<Eigen::Vector3f> points;
  std::vector<float> intensity;
  std::vector<PointColor> colors;
};

// Ray from the sensor at `origin` with unit `d` against z = -1.8 and the facades y = +-8 (first hit, < 60 m).
Scan MakeScan(const Eigen::Vector3d& origin, std::mt19937_64& engine) {
  constexpr int kRings = 32, kColumns = 3750;
  std::normal_distribution<double> noise(0.0, 0.02);
  Scan scan;
  scan.points.reserve(kRings * kColumns);
  for (int c = 0; c < kColumns; ++c) {
    const double azimuth = 2.0 * M_PI * c / kColumns;
    for (int r = 0; r < kRings; ++r) {
      const double elevation = (-30.67 + 1.33 * r) * M_PI / 180.0;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      double range = 60.0;
      if (d.z() < 0) range = std::min(range, (-1.8 - origin.z()) / d.z());
      if (d.y() != 0) range = std::min(range, ((d.y() > 0 ? 8.0 : -8.0) - origin.y()) / d.y());
      if (range >= 60.0) continue;
      const Eigen::Vector3d p = origin + (range + noise(engine)) * d;
      scan.points.push_back(p.cast<float>());
      scan.intensity.push_back(static_cast<float>(r * 8));
      const auto shade = static_cast<std::uint8_t>(static_cast<int>(std::floor(p.x())) & 0xff);
      scan.colors.push_back(std::array<std::uint8_t, 3>{shade, 128, static_cast<std::uint8_t>(r * 8)});
    }
  }
  return scan;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// CPU time of the whole process (all threads), s: on a shared machine it shows the work apart from waiting.
double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
  const int scans = argc > 1 ? std::atoi(argv[1]) : 100;
  uf::mapping::GlobalMapConfig config;
  if (argc > 2) config.voxel_size_m = std::atof(argv[2]);
  auto map = uf::mapping::GlobalMap::Create(config);
  if (!map) {
    std::fprintf(stderr, "%s\n", map.error().c_str());
    return 1;
  }
  std::mt19937_64 engine(42);
  double insert_s = 0, insert_cpu_s = 0;
  std::size_t points = 0;
  for (int k = 0; k < scans; ++k) {
    const Eigen::Vector3d origin(1.0 * k, 0.3 * std::sin(0.1 * k), 0.0);
    const Scan scan = MakeScan(origin, engine);  // not timed
    const auto start = std::chrono::steady_clock::now();
    const double cpu = CpuSeconds();
    const uf::Status status = map->Insert(uf::mapping::WorldScan{k * uf::kNanosecondsPerSecond / 10, origin,
                                                                 scan.points, scan.intensity, scan.colors});
    insert_s += Seconds(start);
    insert_cpu_s += CpuSeconds() - cpu;
    if (!status.ok()) return 1;
    points += scan.points.size();
  }
  const auto stats = map->stats();
  std::printf("ingest: %d scans, %zu points in %.3f s = %.2f M points/s (CPU %.3f s = %.2f M points/s)\n",
              scans, points, insert_s, points / insert_s / 1e6, insert_cpu_s, points / insert_cpu_s / 1e6);
  std::printf("map: %zu voxels (%.1f bytes/voxel), %.1f MiB, %llu colours rejected\n", stats.voxels,
              double(stats.memory_bytes) / double(stats.voxels), stats.memory_bytes / 1048576.0,
              static_cast<unsigned long long>(stats.colors_rejected));

  for (const bool normals : {false, true}) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu = CpuSeconds();
    const uf::mapping::MapView view(*map, {65536, normals});
    std::size_t delivered = 0;
    view.ForEachChunk([&](std::span<const uf::mapping::MapPoint> chunk) {
      delivered += chunk.size();
      return true;
    });
    const double s = Seconds(start);
    std::printf("view%s: %zu points in %.3f s = %.2f M points/s (CPU %.3f s)\n",
                normals ? " with normals" : "", delivered, s, delivered / s / 1e6, CpuSeconds() - cpu);
  }

  const std::filesystem::path file = std::filesystem::temp_directory_path() / "bench_map_ingest.vdb";
  auto start = std::chrono::steady_clock::now();
  double cpu = CpuSeconds();
  if (!uf::mapping::SaveMap(*map, std::nullopt, file).ok()) return 1;
  const double save_s = Seconds(start), save_cpu_s = CpuSeconds() - cpu;
  start = std::chrono::steady_clock::now();
  cpu = CpuSeconds();
  const auto loaded = uf::mapping::LoadMap(file);
  const double load_s = Seconds(start), load_cpu_s = CpuSeconds() - cpu;
  std::printf("map.vdb: %.1f MiB, save %.3f s (CPU %.3f s), load %.3f s (CPU %.3f s) (%s)\n",
              std::filesystem::file_size(file) / 1048576.0, save_s, save_cpu_s, load_s, load_cpu_s,
              loaded.ok() ? "ok" : loaded.error().c_str());
  std::filesystem::remove(file);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak RSS: %.1f MiB\n", usage.ru_maxrss / 1024.0);
  return 0;
}
