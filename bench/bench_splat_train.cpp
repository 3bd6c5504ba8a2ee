// Speed of splat training (SplatTrainer; lavapipe when there is no GPU) on the street scene of
// bench_splat_render: the scene rendered at W x H from 8 poses along the street is the set of target images;
// training starts from the scene with perturbed colours, positions and opacities and runs I iterations over
// those views. Prints iterations per second (wall clock, first iteration excluded: it grows the buffers),
// the device ms per stage, the PSNR of the views before and after, and the peak memory of the process.
// Densification is off unless --densify is given (it changes the model size and so the speed).
// --active-sh A (0 or 3, default 0) times the iterations at active SH degree A of the degree-3 model: 0 is
// where training starts (degree 0 for the first sh_degree_interval = 500 iterations); 3 sets the interval to
// 1 so that the degree is 3 from iteration 3 on, and leaves iterations 0-2 out of the timing.
//
//   bench_splat_train [--gaussians N] [--width W] [--height H] [--iterations I] [--device NAME] [--densify]
//                     [--active-sh A]
#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include "bench/splat_bench_scene.h"
#include "splat/splat_renderer.h"
#include "splat/training/image_metrics.h"
#include "splat/training/splat_trainer.h"

namespace {

using Clock = std::chrono::steady_clock;
using uf::bench::LoadAverage;
using uf::bench::StreetCamera;
using uf::bench::StreetScene;

int Fail(const std::string& message) {
  std::fprintf(stderr, "bench_splat_train: %s\n", message.c_str());
  return 1;
}

// Peak resident memory of this process (VmHWM), MiB.
double PeakMemoryMiB() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return 0;
}

uf::splat::GaussianModel Perturbed(uf::splat::GaussianModel model, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  for (std::size_t i = 0; i < model.size(); ++i) {
    model.positions[i] += 0.02f * Eigen::Vector3f(normal(rng), normal(rng), normal(rng));
    model.opacity_logits[i] = 0.0f;
    for (int c = 0; c < 3; ++c) model.sh[i * model.ShStride() + c] += 0.5f * normal(rng);
  }
  return model;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t gaussians = 100000;
  int width = 320, height = 240, iterations = 50, active_sh = 0;
  bool densify = false;
  uf::splat::SplatRendererOptions device;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--densify"))
      densify = true;
    else if (!std::strcmp(argv[i], "--gaussians") && has_value)
      gaussians = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--width") && has_value)
      width = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--height") && has_value)
      height = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--iterations") && has_value)
      iterations = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--active-sh") && has_value)
      active_sh = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--device") && has_value)
      device.device = argv[++i];
    else
      return Fail(
          "usage: [--gaussians N] [--width W] [--height H] [--iterations I] [--device NAME] [--densify] "
          "[--active-sh 0|3]");
  }
  if (active_sh != 0 && active_sh != 3)
    return Fail("--active-sh must be 0 or 3, got " + std::to_string(active_sh));
  // Iterations before the timing: the first grows the buffers; at active degree 3, 0-2 run at degrees 0-2.
  const int warmup = active_sh == 3 ? 3 : 1;
  if (iterations < warmup + 1) return Fail("--iterations must be >= " + std::to_string(warmup + 1));

  // Target images: the scene itself, rendered by the renderer.
  const uf::splat::GaussianModel truth = StreetScene(gaussians, 7);
  std::vector<uf::splat::TrainingView> views;
  {
    auto renderer = uf::splat::SplatRenderer::Create(device);
    if (!renderer.ok()) return Fail(renderer.error());
    if (auto s = (*renderer)->Upload(truth); !s.ok()) return Fail(s.message());
    for (int v = 0; v < 8; ++v) {
      uf::splat::TrainingView view;
      view.camera = StreetCamera(width, height, 1.0 * v, 0.1 * (v % 3 - 1));
      auto rendered = (*renderer)->Render(view.camera);
      if (!rendered.ok()) return Fail(rendered.error());
      view.rgb = rendered->rgb;
      views.push_back(std::move(view));
    }
  }
  uf::splat::TrainingOptions options;
  options.iterations = iterations;
  if (!densify) options.densify_from = options.densify_until = 0;
  options.opacity_reset_interval = 0;
  if (active_sh == 3) options.sh_degree_interval = 1;
  auto trainer = uf::splat::SplatTrainer::Create(Perturbed(truth, 3), options, 15.0, device);
  if (!trainer.ok()) return Fail(trainer.error());

  auto mean_psnr = [&]() -> double {
    double sum = 0;
    for (const uf::splat::TrainingView& view : views) {
      auto rendered = (*trainer)->Render(view.camera);
      if (!rendered.ok()) return -1;
      sum += uf::splat::Psnr(rendered->rgb, view.rgb);
    }
    return sum / static_cast<double>(views.size());
  };
  const double psnr_before = mean_psnr();
  std::printf("device: %s\n", (*trainer)->device_name().c_str());
  std::printf(
      "scene: %zu Gaussians (SH degree 3, active %d), %d x %d px, %d iterations (%d timed), "
      "densification %s\n",
      gaussians, active_sh, width, height, iterations, iterations - warmup, densify ? "on" : "off");
  std::map<std::string, double> stage_ms;
  std::vector<std::string> stage_order;
  Clock::time_point start = Clock::now();
  uf::splat::IterationStats last;
  for (int it = 0; it < iterations; ++it) {
    if (it == warmup) start = Clock::now();
    auto stats = (*trainer)->Step(views[it % views.size()]);
    if (!stats.ok()) return Fail(stats.error());
    last = *stats;
    if (it < warmup) continue;
    for (const auto& [name, ms] : stats->stage_ms) {
      if (!stage_ms.count(name)) stage_order.push_back(name);
      stage_ms[name] += ms / (iterations - warmup);
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const int timed = iterations - warmup;
  std::printf("training: %.2f iterations/s (%.1f ms per iteration, wall clock, active SH degree %d)\n",
              timed / seconds, 1000 * seconds / timed, last.active_sh_degree);
  std::printf("device ms per stage:");
  for (const std::string& name : stage_order) std::printf(" %s %.2f;", name.c_str(), stage_ms[name]);
  std::printf("\nlast loss %.4f (L1 %.4f, D-SSIM %.4f), Gaussians %zu\n", last.loss, last.l1, last.dssim,
              last.gaussians);
  std::printf("PSNR of the training views: %.2f dB before, %.2f dB after\n", psnr_before, mean_psnr());
  std::printf("peak memory: %.0f MiB\n", PeakMemoryMiB());
  std::printf("load average: %s\n", LoadAverage().c_str());
  return 0;
}
