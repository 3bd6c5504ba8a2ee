// What the optional factors did over a run so far, as the windows that use the providers report it.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/se3.h"

namespace uf::estimator {

// Nearest rank of ascending values (not empty): the smallest value with at least `fraction` of them at or
// below it.
inline double NearestRank(const std::vector<double>& sorted, double fraction) {
  const auto k = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(k, 1, sorted.size()) - 1];
}

// The same over weighted values (weights > 0): the smallest value with at least `fraction` of the total
// weight at or below it (0.5: the weighted median).
struct WeightedValue {
  double value = 0, weight = 0;
};
inline double WeightedRank(const std::vector<WeightedValue>& ascending, double fraction) {
  double total = 0;
  for (const WeightedValue& v : ascending) total += v.weight;
  double sum = 0;
  for (const WeightedValue& v : ascending)
    if ((sum += v.weight) >= fraction * total) return v.value;
  return ascending.back().value;
}

// Factors added, measurements skipped (bad values, no data over the interval, no node near), and rejected
// by an integrity check.
struct FactorCount {
  int added = 0, skipped = 0, rejected = 0;
};
struct SensorFactorStats {
  FactorCount wheel;
  double wheel_scale = 1;  // the estimated wheel scale (1 without wheel factors or with it fixed)
  int wheel_at_rest = 0;   // node intervals held by the stationary branch's zero-motion factor
  FactorCount gnss;
  int gnss_horizontal_only = 0;  // of gnss.added: used without their height (it failed the innovation test)
  int gnss_held_out = 0;         // of gnss.rejected: held out by the step guard (schedule/gnss_step_guard.h)
  // The innovation test over the run (every fix tested before its factor, with a finite prediction): the
  // horizontal innovation's median and 95th percentile, m, and the mean d^2 (the normalized innovation
  // squared: 3 for errors as large as the test's covariances; the fixed prediction sigma makes it smaller
  // for precise fixes).
  struct Innovations {
    int tested = 0;
    double horizontal_median_m = 0, horizontal_p95_m = 0, mean_d2 = 0;
  } gnss_innovations;
  std::string gnss_alignment;  // how the world -> ENU alignment started, or why not yet ("" without GNSS)
  // Camera (VIO, LVIO): reprojection factors added, features seen from enough nodes that left the window
  // without triangulating (skipped), landmarks dropped as outliers (rejected); the camera time offset t_d
  // (camera stamp + t_d = IMU time): the run's estimate and the window's at the end. They are the same but
  // in LVIO with t_d estimated, where the run's is the weighted median of the window's estimates after each
  // solve (camera_time_offset_estimates of them, with their weighted interquartile range; VisualProvider::
  // RecordWindowTimeOffset).
  FactorCount visual;
  double camera_time_offset_s = 0, camera_time_offset_window_s = 0;
  int camera_time_offset_estimates = 0;
  double camera_time_offset_iqr_s = 0;
  int visual_map_depths = 0;            // LVIO: landmarks whose depth came from the LiDAR map
  int visual_map_planes = 0;            // LVIO: of those, held on the map's plane (visual.hold_map_depth)
  // Stereo: frame pairs matched, landmarks whose depth came from their anchor's pair, and the right
  // camera's factors (of visual.added).
  int stereo_pairs = 0, stereo_depths = 0, stereo_factors = 0;
  std::optional<SE3> camera_extrinsic;  // T_body_camera at the end, when it was estimated
  // LiDAR modes: the rings a map block needed for a plane (lo.map.min_plane_rings, or what its auto chose
  // for the LiDAR); 0 without LiDAR.
  int lidar_plane_rings = 0;
  // LWIO: scans whose weak translations were left to the wheel (lio.wheel_carries_weak_translations).
  int lidar_translations_to_wheel = 0;
  // LIO with lio.estimate_lidar_translation: T_body_lidar at the end (its translation estimated), and the
  // window solves that moved the translation (of all the window solves since the initialization).
  std::optional<SE3> lidar_extrinsic;
  int lidar_translation_free_solves = 0, lidar_translation_solves = 0;
};

}  // namespace uf::estimator
