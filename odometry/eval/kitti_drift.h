// KITTI odometry drift as the KITTI devkit (evaluate_odometry.cpp) computes it: segments of 100, 200, ...,
// 800 m measured along the reference path, one start every 10 frames; for each, the pose error E =
// (P_first^-1 P_last)^-1 (Q_first^-1 Q_last) gives a translational error |t_E| / length and a rotational
// error angle(E) / length; the figures are their means, as a percentage and in degrees per 100 m.
// The devkit computes in single precision; this uses double.
// Beside them (not the devkit's), the path scale: the segments' chords |t(last) - t(first)| summed over the
// estimate's against the reference's, less 1. The devkit's error is a norm and hides its sign; this says
// whether the estimate's path is too long (> 0) or too short, and rigid motions leave it unchanged. A scale
// error s leaves about s L / sqrt(12) of SE3-aligned ATE over a straight path of length L.
#pragma once

#include <cstddef>
#include <vector>

#include "odometry/types/se3.h"

namespace uf {

struct KittiDrift {
  double t_pct = 0;           // mean translational error, % of segment length
  double r_deg_per_100m = 0;  // mean rotational error, degrees per 100 m
  double scale_ppm = 0;       // path scale: the estimate's chords over the reference's, less 1, in ppm
  std::size_t segments = 0;   // 0 when the reference path is shorter than 100 m: the figures are undefined
};

KittiDrift ComputeKittiDrift(const std::vector<SE3>& reference, const std::vector<SE3>& estimate);

}  // namespace uf
