// Speed of the Vulkan backward pass (SplatRenderer::Backward; lavapipe when there is no GPU) on the street
// scene of bench_splat_render (N flat Gaussians on the ground and walls, SH degree 3), 320 x 240 by default:
// per iteration one Render and one Backward with random dL/d(rgb, alpha, depth sum). Prints the device ms of
// the backward stages (timestamp queries), the wall-clock ms of Render and Backward (incl. uploads and
// read-backs), and the backward throughput in pixel-Gaussian pairs per second (the forward's pair count
// divided by the device time of the rasterize backward stage).
//
//   bench_splat_backward [--gaussians N] [--width W] [--height H] [--iterations I] [--device NAME]
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

using Clock = std::chrono::steady_clock;
using uf::bench::LoadAverage;
using uf::bench::StreetScene;

int Fail(const std::string& message) {
  std::fprintf(stderr, "bench_splat_backward: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t gaussians = 100000;
  int width = 320, height = 240, iterations = 10;
  uf::splat::SplatRendererOptions options;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--gaussians"))
      gaussians = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--width"))
      width = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--height"))
      height = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--iterations"))
      iterations = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--device"))
      options.device = argv[i + 1];
    else
      return Fail("usage: [--gaussians N] [--width W] [--height H] [--iterations I] [--device NAME]");
  }
  auto renderer = uf::splat::SplatRenderer::Create(options);
  if (!renderer.ok()) return Fail(renderer.error());
  if (auto s = (*renderer)->Upload(StreetScene(gaussians, 7)); !s.ok()) return Fail(s.message());
  const uf::splat::SplatCamera camera = uf::bench::StreetCamera(width, height);

  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  std::mt19937_64 rng(11);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  uf::splat::ViewGradients dL_dview;
  for (std::size_t p = 0; p < 3 * pixels; ++p) dL_dview.rgb.push_back(normal(rng));
  for (std::size_t p = 0; p < pixels; ++p) dL_dview.alpha.push_back(normal(rng));
  for (std::size_t p = 0; p < pixels; ++p) dL_dview.depth_sum.push_back(0.01f * normal(rng));

  std::printf("device: %s\n", (*renderer)->device_name().c_str());
  std::printf("scene: %zu Gaussians (SH degree 3), %d x %d px, %d iterations\n", gaussians, width, height,
              iterations);
  std::map<std::string, double> stage_ms;
  double render_s = 0, backward_s = 0;
  for (int it = -1; it < iterations; ++it) {  // iteration -1 warms up (grows the buffers)
    const Clock::time_point t0 = Clock::now();
    auto view = (*renderer)->Render(camera);
    if (!view.ok()) return Fail(view.error());
    const Clock::time_point t1 = Clock::now();
    auto gradients = (*renderer)->Backward(dL_dview);
    if (!gradients.ok()) return Fail(gradients.error());
    const Clock::time_point t2 = Clock::now();
    if (it < 0) continue;
    render_s += std::chrono::duration<double>(t1 - t0).count();
    backward_s += std::chrono::duration<double>(t2 - t1).count();
    for (const auto& [name, ms] : (*renderer)->last_frame_stats().stage_ms) stage_ms[name] += ms / iterations;
  }
  const uf::splat::SplatFrameStats& stats = (*renderer)->last_frame_stats();
  std::printf("wall clock ms per iteration: render %.1f, backward %.1f (incl. uploads and read-backs)\n",
              1000 * render_s / iterations, 1000 * backward_s / iterations);
  std::printf("device ms per stage:");
  for (const auto& [name, ms] : stage_ms) std::printf(" %s %.2f;", name.c_str(), ms);
  std::printf("\nvisible Gaussians: %zu, tile-Gaussian pairs: %zu, pixel-Gaussian pairs: %llu\n",
              stats.visible_gaussians, stats.tile_gaussian_pairs,
              static_cast<unsigned long long>(stats.pixel_gaussian_pairs));
  if (stage_ms.count("rasterize backward") && stage_ms["rasterize backward"] > 0)
    std::printf("backward rasterization throughput: %.0f M pixel-Gaussian pairs/s\n",
                stats.pixel_gaussian_pairs / (stage_ms["rasterize backward"] * 1e-3) / 1e6);
  std::printf("load average: %s\n", LoadAverage().c_str());
  return 0;
}
