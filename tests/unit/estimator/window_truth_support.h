// What the inertial window's end-to-end tests share (WIO, VIO): a simulated sequence's ground truth, the
// run's ATE and KITTI-style drift against it, and warnings as one text.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "odometry/eval/evaluation.h"
#include "odometry/io/trajectory_file.h"

namespace uf::estimator::testing {

struct TruthFigures {
  Trajectory truth;  // groundtruth.tum of the sequence
  double ate_m = std::numeric_limits<double>::infinity();
  KittiDrift drift;
};

// The estimate against the folder's groundtruth.tum (SE3-aligned ATE, KITTI drift).
inline TruthFigures AgainstTruth(const std::filesystem::path& folder, const Trajectory& estimate) {
  TruthFigures figures;
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  if (!truth) return figures;
  figures.truth = *truth;
  EvalOptions options;
  options.kitti_drift = true;
  auto result = Evaluate(*truth, estimate, options);
  EXPECT_TRUE(result.ok()) << result.error();
  if (result.ok()) {
    figures.ate_m = result->ape.rmse;
    figures.drift = result->kitti_drift.value_or(KittiDrift{});
  }
  return figures;
}

inline std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

}  // namespace uf::estimator::testing
