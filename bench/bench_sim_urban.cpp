// The simulator's generation speed on the reference sequence: 60 s of the `urban` scene with a
// 32-beam LiDAR at 10 Hz, an IMU at 200 Hz, a 640x480 camera at 10 Hz, wheel odometry and GNSS (the
// defaults of `ultrafusion sim`). Writes into a temporary folder, removes it, and prints wall time per stage,
// sweeps and frames per second, bytes written, the machine's load and the peak memory.
//
//   bench_sim_urban [--duration S] [--bag] [--keep DIR]
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "odometry/sim/sequence/sequence_generator.h"

namespace fs = std::filesystem;

namespace {

std::uintmax_t FolderBytes(const fs::path& folder) {
  std::uintmax_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  uf::sim::SimulationConfig config;  // the defaults are the reference sequence
  std::string keep;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--duration" && i + 1 < argc) {
      config.duration_s = std::atof(argv[++i]);
    } else if (arg == "--bag") {
      config.write_bag = true;
    } else if (arg == "--keep" && i + 1 < argc) {
      keep = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_sim_urban [--duration S] [--bag] [--keep DIR]\n");
      return 2;
    }
  }
  double load_before[3] = {0, 0, 0};
  getloadavg(load_before, 3);
  const fs::path out = keep.empty() ? fs::temp_directory_path() / ("uf_bench_sim_" + std::to_string(getpid()))
                                    : fs::path(keep);
  const auto start = std::chrono::steady_clock::now();
  auto summary = uf::sim::GenerateSequence(config, out);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!summary) {
    std::fprintf(stderr, "bench_sim_urban: %s\n", summary.error().c_str());
    return 1;
  }
  const std::uintmax_t bytes = FolderBytes(out);
  if (keep.empty()) fs::remove_all(out);
  double load_after[3] = {0, 0, 0};
  getloadavg(load_after, 3);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);

  std::int64_t sweeps = 0, frames = 0;
  for (const auto& stream : summary->streams) {
    if (stream.name == "lidar") sweeps = stream.count;
    if (stream.name == "cam0") frames = stream.count;
  }
  std::printf("bench_sim_urban: %.0f s of '%s' (%.0f m path, %zu triangles)%s\n", summary->duration_s,
              summary->scene.c_str(), summary->path_length_m, summary->scene_triangles,
              config.write_bag ? " with --bag" : "");
  std::printf("  wall time           %8.1f s  (budget 60 s)\n", wall);
  std::printf("    scene + BVH       %8.2f s\n", summary->seconds_scene);
  std::printf("    sensors + writing %8.1f s\n", summary->seconds_sensors);
  std::printf("  lidar sweeps        %8lld  (%lld points)\n", static_cast<long long>(sweeps),
              static_cast<long long>(summary->lidar_points));
  std::printf("  camera frames       %8lld\n", static_cast<long long>(frames));
  std::printf("  sweeps+frames / s   %8.1f\n", (sweeps + frames) / summary->seconds_sensors);
  std::printf("  written             %8.1f MB\n", bytes / 1e6);
  std::printf("  peak memory         %8.0f MB\n", usage.ru_maxrss / 1024.0);
  std::printf("  load average        %.2f before, %.2f after (1 min)\n", load_before[0], load_after[0]);
  return 0;
}
