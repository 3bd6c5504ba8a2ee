#include "viewer/app/cli/splat_command.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/pipeline/progress_line.h"
#include "viewer/pipeline/splat/splat_job.h"

namespace uf::app {

using pipeline::ProgressLine;
using pipeline::RunSplatJob;
using pipeline::SplatJobCallbacks;
using pipeline::SplatJobOptions;
using pipeline::SplatJobResult;
using pipeline::SplatMetrics;
using pipeline::TrainingSize;
namespace {

struct SplatArguments {
  std::string run_dir, config, device, poses;
  int iterations = 0, sh_degree = -1;  // 0 / -1: from the config
  std::vector<int> resolution;         // W H
  double time_budget_s = -1;           // < 0: from the config
};

// Defaults, then --config FILE, then the options given on the command line.
Expected<SplatConfig> ResolveConfig(const SplatArguments& a) {
  SplatConfig config;
  if (!a.config.empty()) {
    Expected<ConfigFile> loaded = LoadConfigFile(a.config);
    if (!loaded) return loaded.status();
    config = loaded->splat;
  }
  if (a.iterations > 0) config.training.iterations = a.iterations;
  if (a.sh_degree >= 0) config.training.sh_degree = a.sh_degree;
  if (a.resolution.size() == 2) config.width = a.resolution[0], config.height = a.resolution[1];
  if (a.time_budget_s >= 0) config.time_budget_s = a.time_budget_s;
  if (Status s = config.Validate(); !s.ok()) return s;
  return config;
}

void PrintSummary(const std::string& run_dir, const SplatJobResult& result) {
  const SplatMetrics& m = result.metrics;
  std::printf("splat: %d iterations in %.1f s (%.2f it/s%s) on %s, %d x %d px, %zu -> %zu Gaussians\n",
              m.iterations, m.seconds, m.iterations_per_s(), m.stopped_by_time ? ", time budget reached" : "",
              m.device.c_str(), m.width, m.height, m.gaussians_initial, m.gaussians);
  std::printf(
      "  held-out views: %zu, PSNR %.2f dB (seeded: %.2f dB), SSIM %.3f; training views: %zu, PSNR %.2f dB\n",
      m.views_test, m.test.psnr, m.psnr_test_initial, m.test.ssim, m.views_train, m.train.psnr);
  if (m.sizes.size() > 1) {
    std::printf("  coarse to fine:");
    for (std::size_t i = 0; i < m.sizes.size(); ++i) {
      const TrainingSize& s = m.sizes[i];
      std::printf("%s %d x %d px %d iterations in %.1f s (%.2f it/s)", i == 0 ? "" : ",", s.width, s.height,
                  s.iterations, s.seconds, s.seconds > 0 ? s.iterations / s.seconds : 0.0);
    }
    std::printf("\n");
  }
  if (m.iterations > 0 && !m.stage_seconds.empty()) {
    std::printf("  time per iteration:");
    for (std::size_t i = 0; i < m.stage_seconds.size(); ++i)
      std::printf("%s %s %.1f ms", i == 0 ? "" : ",", m.stage_seconds[i].first.c_str(),
                  1e3 * m.stage_seconds[i].second / m.iterations);
    std::printf("\n");
  }
  std::printf(
      "  seeds: %zu map points (%zu that no camera saw left out), %zu triangulated corners, %zu sky\n",
      m.map_seeds, m.unseen_map_points, m.feature_seeds, m.sky_gaussians);
  std::printf("  camera %s: %lld images, %lld outside the trajectory\n", m.camera.c_str(),
              static_cast<long long>(m.images), static_cast<long long>(m.images_outside_trajectory));
  std::printf("  wrote %s: splats.ply, splats.glb, metrics.json, comparisons/, plots/splat_loss.png\n",
              run_dir.c_str());
}

int RunSplat(const SplatArguments& a) {
  Expected<SplatConfig> config = ResolveConfig(a);
  if (!config) return ReportUsageError(config.status());
  SplatJobOptions options;
  options.config = *config;
  options.device = a.device;
  options.poses = a.poses;
  Expected<SplatJobResult> result = [&] {
    ProgressLine progress("splat");
    SplatJobCallbacks callbacks;
    callbacks.progress = [&](const std::string& phase, std::int64_t done, std::int64_t total,
                             const std::string& unit) { progress.Update(phase, done, total, unit); };
    callbacks.warning = [&](const std::string& warning) {
      progress.EndLine();
      std::cerr << "ultrafusion: warning: " << warning << "\n";
    };
    return RunSplatJob(a.run_dir, options, callbacks);
  }();
  if (!result) return ReportError(result.status());
  PrintSummary(a.run_dir, *result);
  return kExitOk;
}

}  // namespace

Subcommand AddSplatCommand(CLI::App& app) {
  auto a = std::make_shared<SplatArguments>();
  CLI::App* command = app.add_subcommand(
      "splat",
      "Train Gaussian splats on a run's keyframe images (seeded from its map, placed by its trajectory)");
  command
      ->add_option("RUN_DIR", a->run_dir,
                   "Folder of an `ultrafusion run` (run.json, map.vdb, trajectory.tum)")
      ->required()
      ->check(CLI::ExistingDirectory);
  command->add_option("--iterations", a->iterations, "Optimizer steps, one image each (default 3000)")
      ->check(CLI::Range(1, 100000000));
  command
      ->add_option("--resolution", a->resolution,
                   "Training image size W H, px (default: the camera's halved until W <= 320)")
      ->expected(2)
      ->check(CLI::Range(1, 16384));
  command->add_option("--sh-degree", a->sh_degree, "Final spherical-harmonics degree, 0..3 (default 3)")
      ->check(CLI::Range(0, 3));
  command->add_option("--config", a->config, "YAML file with a splat: section (see configs/splat.yaml)")
      ->check(CLI::ExistingFile);
  command->add_option(
      "--device", a->device,
      "Vulkan device: index or part of its name (default: a GPU if any, else lavapipe on the CPU)");
  command
      ->add_option("--poses", a->poses,
                   "TUM file of the run's output frame to place the images with (default: RUN_DIR/"
                   "trajectory.tum; same frame and world)")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--time-budget", a->time_budget_s, "Stop training after this many seconds (0: no limit)")
      ->check(CLI::Range(0.0, 1e9));
  return {command, [a] { return RunSplat(*a); }};
}

}  // namespace uf::app
