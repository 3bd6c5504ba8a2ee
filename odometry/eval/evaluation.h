// Trajectory accuracy of an estimate against a reference, as evo's evo_ape / evo_rpe compute it:
// associate, align the estimate onto the reference, then absolute (APE) and relative (RPE) translation
// errors, and optionally KITTI drift.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/types/alignment.h"
#include "odometry/eval/association.h"
#include "odometry/eval/kitti_drift.h"
#include "odometry/eval/relative_pose_error.h"
#include "odometry/eval/statistics.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

struct EvalOptions {
  Stamp max_dt = 10'000'000;  // 0.01 s, evo's default t_max_diff
  Stamp estimate_offset = 0;  // added to the estimate's stamps
  AlignMode align = AlignMode::kSe3;
  double rpe_delta = 1;
  RpeUnit rpe_unit = RpeUnit::kFrames;
  bool kitti_drift = false;
};

struct EvalResult {
  Association association;
  Similarity alignment;                  // identity for AlignMode::kNone
  std::vector<SE3> reference, estimate;  // matched poses; estimate aligned
  bool stamped = true;                   // false when paired by index (stampless KITTI files)
  std::vector<double> seconds;           // per matched pair, from the first (index when stampless)
  std::vector<double> ape_errors;        // |t_ref - t_est| per matched pair, metres
  ErrorStats ape;
  IndexPairs rpe_pairs;  // into the matched poses
  std::vector<double> rpe_errors;
  std::optional<ErrorStats> rpe;          // absent when the delta leaves no pair
  std::optional<KittiDrift> kitti_drift;  // when requested
};

Expected<EvalResult> Evaluate(const Trajectory& reference, const Trajectory& estimate,
                              const EvalOptions& options);

}  // namespace uf
