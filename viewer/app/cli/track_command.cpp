#include "viewer/app/cli/track_command.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/pipeline/progress_line.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/stages/reliability_files.h"
#include "viewer/pipeline/track/track_job.h"

namespace uf::app {
namespace {

struct TrackArguments {
  std::string dataset, out, config, camera, stereo, mask;
  int overlay_every = 20;
  std::int64_t max_frames = 0;
  estimator::FeatureTrackerConfig tracker;
};

// The means over the frames that found their stereo partner.
void PrintStereo(const pipeline::TrackResult& r) {
  double pairs = 0, stereo_features = 0, matched = 0, stereo_epipolar = 0;
  for (const std::optional<estimator::StereoStats>& pair : r.stereo) {
    if (!pair) continue;
    ++pairs;
    stereo_features += pair->features;
    matched += pair->matched;
    stereo_epipolar += pair->epipolar_px;
  }
  std::printf("  stereo %s: %.0f pairs, %.1f of %.1f features matched, epipolar distance %.3f px (means)\n",
              r.stereo_stream.c_str(), pairs, matched / std::max(1.0, pairs),
              stereo_features / std::max(1.0, pairs), stereo_epipolar / std::max(1.0, pairs));
}

void PrintResult(const pipeline::TrackResult& r) {
  std::printf("track: %s (%d x %d): %zu frames tracked", r.camera_stream.c_str(), r.width, r.height,
              r.frames.size());
  if (r.undecodable + r.refused > 0)
    std::printf(", %lld skipped (%lld undecodable, %lld refused)",
                static_cast<long long>(r.undecodable + r.refused), static_cast<long long>(r.undecodable),
                static_cast<long long>(r.refused));
  std::printf("\n");
  if (r.frames.empty()) return;
  double features = 0, ratio = 0, occupancy = 0, epipolar = 0;
  int keyframes = 0, poor = 0;
  std::string first_poor;
  std::vector<double> ms;
  for (const estimator::FrameTrackStats& s : r.frames) {
    features += s.features;
    ratio += s.tracked_ratio;
    occupancy += s.grid_occupancy;
    epipolar += s.epipolar_error_px;
    keyframes += s.keyframe;
    if (!s.warning.empty() && poor++ == 0) first_poor = StampText(s.stamp) + ": " + s.warning;
    ms.push_back(s.time_ms);
  }
  const double n = static_cast<double>(r.frames.size());
  std::printf(
      "  features %.1f of %d, tracked ratio %.3f, grid occupancy %.3f, epipolar error %.3f px (means)\n",
      features / n, r.max_features, ratio / n, occupancy / n, epipolar / n);
  std::printf("  keyframes %d; poor frames %d%s%s\n", keyframes, poor, poor > 0 ? ", the first at " : "",
              first_poor.c_str());
  int degenerate = 0;
  for (const estimator::CameraDegeneracy& d : r.degeneracy)
    degenerate += d.score >= pipeline::kDegenerateReported;
  std::printf("  camera degeneracy D >= %.1f in %d of %zu frames\n", pipeline::kDegenerateReported,
              degenerate, r.frames.size());
  if (!r.stereo_stream.empty()) PrintStereo(r);
  const pipeline::TimingSummary timing = pipeline::SummarizeTimings(ms);
  std::printf("  time per frame: mean %.2f ms, p95 %.2f ms\n", timing.mean, timing.p95);
  if (!r.warnings.empty())
    std::printf("  %zu warnings, the first: %s\n", r.warnings.size(), r.warnings[0].c_str());
}

int RunTrackCommand(const TrackArguments& a) {
  pipeline::TrackRequest request;
  request.dataset = a.dataset;
  request.camera = a.camera;
  request.stereo_camera = a.stereo;
  request.mask = a.mask;
  request.overlay_every = a.overlay_every;
  request.max_frames = a.max_frames;
  request.tracker = a.tracker;
  if (!a.config.empty()) {
    Expected<ConfigFile> loaded = LoadConfigFile(a.config);
    if (!loaded) return ReportUsageError(loaded.status());
    request.dataset_config = loaded->dataset;
  }
  pipeline::ProgressLine progress("track");
  Expected<pipeline::TrackResult> result = pipeline::RunTrack(
      request, [&](std::int64_t frames) { progress.Update("tracking", frames, 0, "frames"); });
  progress.EndLine();
  if (!result) return ReportError(result.status());
  PrintResult(*result);
  if (!a.out.empty()) {
    Expected<std::vector<std::string>> written = pipeline::WriteTrackOutputs(a.out, *result);
    if (!written) return ReportError(written.status());
    std::printf("  wrote %s: tracks.csv, %zu plots\n", a.out.c_str(), written->size() - 1);
  }
  return kExitOk;
}

}  // namespace

Subcommand AddTrackCommand(CLI::App& app) {
  auto a = std::make_shared<TrackArguments>();
  CLI::App* command = app.add_subcommand(
      "track", "Run the visual front end (corners, KLT tracks, epipolar check) over a dataset's camera");
  command->add_option("DATASET", a->dataset, "ROS1 .bag file, or a KITTI raw, EuRoC or ultrafusion folder")
      ->required();
  command->add_option("--out", a->out, "Folder for tracks.csv and plots/ (created)");
  command->add_option("--config", a->config, "YAML file with a dataset: section")->check(CLI::ExistingFile);
  command->add_option("--camera", a->camera, "Camera stream name (default: the first camera)");
  command->add_option("--stereo", a->stereo,
                      "Second camera stream: match every frame in it (needs both cameras' extrinsics)");
  command->add_option("--mask", a->mask, "Image of the camera's size whose black pixels get no features")
      ->check(CLI::ExistingFile);
  command->add_option("--overlay-every", a->overlay_every, "Write an overlay of every N-th frame (0: none)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  command->add_option("--max-frames", a->max_frames, "Stop after this many frames (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_option("--max-features", a->tracker.max_features, "Features kept per frame")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  command->add_option("--min-distance", a->tracker.min_distance_px, "Least distance between features, px")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  command
      ->add_option(
          "--smoothing", a->tracker.smoothing_sigma_px,
          "Gaussian smoothing of every frame before tracking, px (0: none; for a camera that aliases, "
          "as the simulator's: 0.8)")
      ->check(CLI::Range(0.0, estimator::FeatureTrackerConfig::kMaxSmoothingSigmaPx))
      ->capture_default_str();
  return {command, [a] { return RunTrackCommand(*a); }};
}

}  // namespace uf::app
