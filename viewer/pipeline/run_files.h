// The files `ultrafusion run` writes into its output folder besides the report: the trajectory (TUM and
// KITTI), timing.json and any text file, each written under a temporary name and renamed into place so a
// failure never leaves a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::pipeline {

// Milliseconds per step of the estimator (a scan of the LiDAR window, a node of the wheel-inertial one),
// summarised.
struct TimingSummary {
  std::size_t steps = 0;
  double mean = 0, median = 0, p95 = 0, max = 0;
};

// Where a LiDAR window's scan went (the estimator's OdometryStats), ms: preparation (range filter,
// downsampling), plane association, the new scan's registration solves, the window's solve, map insertion,
// marginalization. Per scan, or their means over a run.
struct StageTimes {
  double prepare = 0, associate = 0, register_scan = 0, window = 0, map = 0, marginalize = 0;

  StageTimes& operator+=(const StageTimes& o) {
    prepare += o.prepare, associate += o.associate, register_scan += o.register_scan;
    window += o.window, map += o.map, marginalize += o.marginalize;
    return *this;
  }
  StageTimes operator/(double n) const {
    return {prepare / n, associate / n, register_scan / n, window / n, map / n, marginalize / n};
  }
};

// Mean, median, 95th percentile (nearest rank: the smallest value with >= 95 % of the values at or below
// it) and maximum; all zero for no steps.
TimingSummary SummarizeTimings(std::vector<double> milliseconds);

// trajectory.tum (stamps with nine decimals, nanosecond-exact) and trajectory_kitti.txt (12 numbers of the
// 3x4 matrix [R|t] per line) in `folder`.
Status WriteTrajectoryFiles(const std::filesystem::path& folder, const Trajectory& trajectory);

// {"scans": N, "ms_per_scan": {"mean", "median", "p95", "max"}, "skipped": S, "warnings": W}, with `step`
// ("scan" or "node") in the first two keys, and with `stages` "stage_ms_mean": {"prepare", "associate",
// "register", "window", "map", "marginalize"}.
Status WriteTimingJson(const std::filesystem::path& path, const TimingSummary& timing, std::int64_t skipped,
                       std::int64_t warnings, const std::string& step,
                       const std::optional<StageTimes>& stages = std::nullopt);

// plots/timing_per_<step>.png: milliseconds per step against its time from the first one, with the mean,
// median and RMS as lines (the eval error plot, its "error" series being the time per step).
// stamps.size() == milliseconds.size(), not empty.
Status WriteTimingPlot(const std::filesystem::path& png, const std::vector<Stamp>& stamps,
                       const std::vector<double>& milliseconds, const std::string& step);

Status WriteTextFileAtomically(const std::filesystem::path& path, const std::string& text);
Status WriteBinaryFileAtomically(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);

}  // namespace uf::pipeline
