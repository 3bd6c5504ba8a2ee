// bench_feature_tracker: the visual front end (uf::estimator::FeatureTracker, default config) over the frames
// of one camera stream of a dataset: time per frame (mean / p50 / p95 / max; decoding excluded), features,
// tracked ratio, grid occupancy, epipolar error, keyframes and poor frames, with the machine's load average.
// Nothing is asserted. Any dataset `info` reads works: a simulated folder (`ultrafusion sim`, 640x480),
// EuRoC (752x480), KITTI raw (1242x375).
//   usage: bench_feature_tracker DATASET [--camera K] [--frames N]
//   K: the K-th camera stream (0: the first); N: at most this many frames (default 300)
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"
#include "odometry/types/process_memory.h"

int main(int argc, char** argv) {
  using namespace uf;
  using uf::bench::LoadAverage;
  using uf::bench::Percentile;
  KeepFreedMemoryForReuse();  // as the ultrafusion binary does
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_feature_tracker DATASET [--camera K] [--frames N]\n");
    return 2;
  }
  int camera_index = 0, max_frames = 300;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--camera") camera_index = std::stoi(argv[i + 1]);
    if (std::string(argv[i]) == "--frames") max_frames = std::stoi(argv[i + 1]);
  }
  auto reader = OpenDataset(argv[1]);
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.error().c_str());
    return 1;
  }
  const DatasetDescription& description = (*reader)->description();
  int stream = -1;
  for (int s = 0, cameras = 0; s < static_cast<int>(description.streams.size()); ++s)
    if (description.streams[s].kind == SensorKind::kCamera && cameras++ == camera_index) stream = s;
  if (stream < 0 || !description.streams[stream].camera_model) {
    std::fprintf(stderr, "%s: no camera stream %d with intrinsics\n", argv[1], camera_index);
    return 1;
  }
  std::vector<CameraFrame> frames;
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    auto* frame = std::get_if<CameraFrame>(&m.data);
    if (m.stream != stream || !frame || static_cast<int>(frames.size()) >= max_frames) return Status();
    if (Status decoded = DecodeCameraFrame(*frame); !decoded.ok()) return decoded;
    frames.push_back(std::move(*frame));
    return Status();
  });
  if (!read.ok()) std::fprintf(stderr, "read: %s\n", read.message().c_str());
  const CameraModel& model = *description.streams[stream].camera_model;
  auto tracker = estimator::FeatureTracker::Create(model, {});
  if (!tracker.ok()) {
    std::fprintf(stderr, "%s\n", tracker.error().c_str());
    return 1;
  }
  std::printf("bench_feature_tracker: %s, camera %s (%d x %d), %zu frames, load average before %s\n", argv[1],
              description.streams[stream].name.c_str(), model.width(), model.height(), frames.size(),
              LoadAverage().c_str());
  std::vector<double> ms;
  double features = 0, tracked_ratio = 0, occupancy = 0, epipolar = 0;
  double lost_klt = 0, lost_fb = 0, lost_ransac = 0, lost_spacing = 0;
  int keyframes = 0, poor = 0, refused = 0;
  for (const CameraFrame& frame : frames) {
    const auto start = std::chrono::steady_clock::now();
    auto tracked = tracker->Track(frame.stamp, frame.image);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    if (!tracked.ok()) {
      ++refused;
      continue;
    }
    const estimator::FrameTrackStats& s = tracked->stats;
    features += s.features;
    tracked_ratio += s.tracked_ratio;
    occupancy += s.grid_occupancy;
    epipolar += s.epipolar_error_px;
    lost_klt += s.lost_klt, lost_fb += s.lost_fb, lost_ransac += s.lost_ransac,
        lost_spacing += s.lost_spacing;
    keyframes += s.keyframe;
    poor += !s.warning.empty();
  }
  const double n = std::max<double>(1.0, static_cast<double>(frames.size() - refused));
  double total = 0;
  for (double v : ms) total += v;
  std::printf("  time per frame: mean %.2f ms, p50 %.2f, p95 %.2f, max %.2f\n",
              total / std::max<double>(1, ms.size()), Percentile(ms, 0.5), Percentile(ms, 0.95),
              Percentile(ms, 1.0));
  std::printf("  features %.1f, tracked ratio %.3f, grid occupancy %.3f, epipolar error %.3f px\n",
              features / n, tracked_ratio / n, occupancy / n, epipolar / n);
  std::printf("  lost per frame: KLT %.1f, forward-backward %.1f, RANSAC %.1f, spacing %.1f\n", lost_klt / n,
              lost_fb / n, lost_ransac / n, lost_spacing / n);
  std::printf("  keyframes %d, poor frames %d, refused frames %d\n", keyframes, poor, refused);
  std::printf("  load average after %s\n", LoadAverage().c_str());
  return 0;
}
