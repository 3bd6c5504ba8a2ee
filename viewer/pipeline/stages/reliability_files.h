// The reliability scores of a run (docs/METHOD.md "Factor-wise reliability scheduling"): reliability.csv,
// one row per keyframe and modality with the score D, the inputs it came from and whether the modality's
// factors were active, and plots/reliability_lidar.png (D over time). Only the LiDAR is scored so far, and
// nothing is scheduled yet: `active` is 1 on every row.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/types/keyframe.h"
#include "odometry/types/status.h"

namespace uf::pipeline {

// The LiDAR degeneracy the report lists as spans, and the plot marks: D >= 0.5 (the weakest direction with
// under half the information of the healthy isotropy, lidar_degeneracy.h).
constexpr double kDegenerateReported = 0.5;

struct ScoredKeyframe {
  Stamp stamp = 0;
  LidarDegeneracy lidar;
};

// Where the LiDAR was degenerate (D >= threshold) as time intervals, for the report: [first, last] stamps
// of each run of consecutive keyframes at or above it.
struct DegenerateSpan {
  Stamp first = 0, last = 0;
  int keyframes = 0;
  double worst = 0;  // the highest D in it
};
std::vector<DegenerateSpan> DegenerateSpans(const std::vector<ScoredKeyframe>& scored, double threshold);

// Writes folder/reliability.csv and folder/plots/reliability_lidar.png (the plot only with a keyframe);
// returns the files written, relative to folder. Errors: a file that cannot be written (nothing half
// written is left behind).
Expected<std::vector<std::string>> WriteReliabilityFiles(const std::filesystem::path& folder,
                                                         const std::vector<ScoredKeyframe>& scored);

}  // namespace uf::pipeline
