// The accuracy stage of `ultrafusion run`: trajectory.tum against the ground truth found beside the dataset,
// computed exactly as `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` does (SE3 Umeyama
// alignment, max_dt 0.01 s, RPE over 1 frame), with its plots in plots/. An evaluation that is not possible
// (a trajectory too short or straight to align, stamps that do not match) is a finding of the report, not a
// failure of the run.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odometry/eval/evaluation_report.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

// The accuracy section: the eval table, the plots written, or why there is none.
struct GroundTruthCheck {
  bool evaluated = false;
  double ape_rmse_m = 0;
  std::size_t matched_poses = 0;   // estimated poses paired with the ground truth
  std::string table;               // as `ultrafusion eval` prints it
  std::vector<std::string> plots;  // paths relative to the output folder
  std::string note;                // "no ground truth in the dataset", or the evaluation's error
};

// Reads both trajectories, evaluates and writes the APE/RPE plots into out_folder/plots. Never fails:
// problems end up in `note`.
GroundTruthCheck EvaluateAgainstGroundTruth(const std::filesystem::path& ground_truth,
                                            const std::filesystem::path& out_folder,
                                            const std::string& estimate_file);

// The stage on out/trajectory.tum; its message says why an evaluation was not possible.
GroundTruthCheck RunAccuracyStage(const std::filesystem::path& ground_truth, const std::filesystem::path& out,
                                  StageContext& context);

}  // namespace uf::pipeline
