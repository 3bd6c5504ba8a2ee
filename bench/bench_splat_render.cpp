// Splat rendering speed of the Vulkan compute renderer (lavapipe when there is no GPU): a street-like scene
// of N flat Gaussians on surfaces (ground 2-30 m ahead, side walls, a far wall; tangent sizes 1-10 cm, SH
// degree 3), a 1.5 m high camera looking down the street, 640 x 480. Prints the device, frames/s, ms per
// frame (wall clock, including the read-back), device ms per stage (timestamp queries), the pair counts and
// the forward rasterization throughput in pixel-Gaussian pairs per second, and the process's peak memory
// (device memory is host memory on lavapipe).
//
//   bench_splat_render [--gaussians N] [--width W] [--height H] [--frames F] [--device NAME]
#include <sys/resource.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include "bench/splat_bench_scene.h"
#include "splat/splat_renderer.h"

namespace {

using uf::bench::LoadAverage;
using uf::bench::StreetScene;

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t gaussians = 100000;
  int width = 640, height = 480, frames = 10;
  uf::splat::SplatRendererOptions options;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--gaussians"))
      gaussians = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--width"))
      width = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--height"))
      height = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--frames"))
      frames = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--device"))
      options.device = argv[i + 1];
    else {
      std::fprintf(stderr,
                   "usage: bench_splat_render [--gaussians N] [--width W] [--height H] [--frames F] "
                   "[--device NAME]\n");
      return 2;
    }
  }
  auto renderer = uf::splat::SplatRenderer::Create(options);
  if (!renderer.ok()) {
    std::fprintf(stderr, "bench_splat_render: %s\n", renderer.error().c_str());
    return 1;
  }
  const uf::splat::GaussianModel model = StreetScene(gaussians, 7);
  if (auto s = (*renderer)->Upload(model); !s.ok()) {
    std::fprintf(stderr, "bench_splat_render: %s\n", s.message().c_str());
    return 1;
  }
  const uf::splat::SplatCamera camera = uf::bench::StreetCamera(width, height);

  std::printf("device: %s\n", (*renderer)->device_name().c_str());
  std::printf("scene: %zu Gaussians (SH degree 3), %d x %d px\n", gaussians, width, height);
  auto first = (*renderer)->Render(camera);  // warm-up: grows the frame buffers
  if (!first.ok()) {
    std::fprintf(stderr, "bench_splat_render: %s\n", first.error().c_str());
    return 1;
  }
  std::map<std::string, double> stage_ms;
  double rasterize_ms = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    auto view = (*renderer)->Render(camera);
    if (!view.ok()) {
      std::fprintf(stderr, "bench_splat_render: %s\n", view.error().c_str());
      return 1;
    }
    for (const auto& [name, ms] : (*renderer)->last_frame_stats().stage_ms) stage_ms[name] += ms / frames;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const uf::splat::SplatFrameStats& stats = (*renderer)->last_frame_stats();
  std::printf("frames/s: %.2f (%.1f ms per frame over %d frames, wall clock incl. read-back)\n",
              frames / seconds, 1000 * seconds / frames, frames);
  std::printf("device ms per stage:");
  for (const auto& [name, ms] : stage_ms) std::printf(" %s %.2f;", name.c_str(), ms);
  std::printf("\n");
  rasterize_ms = stage_ms.count("rasterize") ? stage_ms["rasterize"] : 0;
  std::printf("visible Gaussians: %zu, tile-Gaussian pairs: %zu, pixel-Gaussian pairs: %llu\n",
              stats.visible_gaussians, stats.tile_gaussian_pairs,
              static_cast<unsigned long long>(stats.pixel_gaussian_pairs));
  if (rasterize_ms > 0)
    std::printf("forward rasterization throughput: %.0f M pixel-Gaussian pairs/s\n",
                stats.pixel_gaussian_pairs / (rasterize_ms * 1e-3) / 1e6);
  std::printf("peak memory: %.0f MiB; load average: %s\n", PeakMemoryMiB(), LoadAverage().c_str());
  return 0;
}
