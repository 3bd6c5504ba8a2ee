// The accuracy stage of `ultrafusion run`: trajectory.tum against the ground truth found beside the dataset,
// computed exactly as `ultrafusion eval GROUND_TRUTH trajectory.tum --align se3` does (SE3 Umeyama
// alignment, max_dt 0.01 s, RPE over 1 frame), with its plots in plots/; without ground truth, against the
// run's GNSS fixes (odometry/eval/gnss_track_error.h). An evaluation that is not possible (a trajectory
// too short or straight to align, stamps that do not match) is a finding of the report, not a failure of
// the run.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "odometry/eval/evaluation_report.h"
#include "odometry/eval/gnss_track_error.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/georeference.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

// The georeferenced trajectory against a ground truth in a known ENU frame, without any alignment: the
// ground truth's positions moved into the run's ENU frame through WGS84 (odometry/types/geodetic.h).
struct EnuAccuracy {
  double rmse_m = 0, horizontal_rmse_m = 0, vertical_rmse_m = 0;
  std::size_t matched_poses = 0;
};

// The accuracy section: the eval table, the plots written, or why there is none.
struct GroundTruthCheck {
  bool evaluated = false;
  double ape_rmse_m = 0;
  // A gravity-aligned run (any mode but LO) against a ground-truth file (its world taken to have z up): the
  // ATE aligned by yaw and translation only (`eval --align yaw`), where a tilt of the run's world counts;
  // none otherwise.
  std::optional<double> yaw_ape_rmse_m;
  std::size_t matched_poses = 0;   // estimated poses paired with the ground truth
  std::string table;               // as `ultrafusion eval` prints it
  std::vector<std::string> plots;  // paths relative to the output folder
  std::string note;                // "no ground truth in the dataset", or the evaluation's error
  std::string reference_source;    // the reader's reference, when that was the ground truth (reference.tum)
  bool ground_truth_moved_to_output_frame = false;  // the ground-truth file, body frame, taken to
                                                    // trajectory.tum's (reference.tum)
  std::optional<EnuAccuracy> enu;  // a run georeferenced by the estimator, a ground truth with an ENU origin
  std::string enu_note;            // why there is no ENU figure for a georeferenced run
  std::optional<GnssTrackError> gnss_track;  // without ground truth: trajectory.tum against the GNSS fixes
  std::string gnss_track_note;               // why there is no GNSS-track figure
};

// What the GNSS-track comparison needs beside trajectory.tum.
struct GnssTrackInput {
  std::span<const GnssFix> fixes;
  SE3 T_frame_antenna;          // the antenna in trajectory.tum's frame
  bool gravity_aligned = true;  // trajectory.tum's world has z up (LIO, WIO)
};

// The ENU frames of a georeferenced estimate and of its ground truth (EvaluateInEnu).
struct EnuOrigins {
  GeodeticOrigin truth, run;
};

// Reads both trajectories, evaluates and writes the APE/RPE plots into out_folder/plots; with `enu`, the
// unaligned ENU figures too (EvaluateInEnu); with `gravity_aligned` (the estimate's world has z up), the
// yaw-aligned ATE too. Never fails: problems end up in `note` / `enu_note`.
GroundTruthCheck EvaluateAgainstGroundTruth(const std::filesystem::path& ground_truth,
                                            const std::filesystem::path& out_folder,
                                            const std::string& estimate_file,
                                            const std::optional<EnuOrigins>& enu = std::nullopt,
                                            bool gravity_aligned = false);

// trajectory_enu (T_enu_F, ENU at run_origin) against the ground truth (its world ENU at truth_origin, same
// body frame F), matched within 0.01 s.
Expected<EnuAccuracy> EvaluateInEnu(const Trajectory& ground_truth, const GeodeticOrigin& truth_origin,
                                    const Trajectory& trajectory_enu, const GeodeticOrigin& run_origin);

// The stage on out/trajectory.tum; its message says why an evaluation was not possible. A ground-truth file
// (poses of the dataset's body frame B) is evaluated as it is when trajectory.tum is in B, else taken to
// trajectory.tum's frame first (out/reference.tum, as below). Without a
// ground-truth file, a reference the reader derived (DatasetDescription::reference) is written to
// out/reference.tum in trajectory.tum's frame F (T_output_body = T_F_B) and evaluated against instead. With
// the estimator's georeference, trajectory.tum is in ENU: with the ground truth's ENU origin the check also
// has the unaligned ENU figures. Without ground truth, with fixes: the GNSS-track figures (unaligned when
// georeferenced).
GroundTruthCheck RunAccuracyStage(const DatasetDescription& description, const std::filesystem::path& out,
                                  const std::optional<Georeference>& georef, const GnssTrackInput& gnss,
                                  const SE3& T_output_body, StageContext& context);

}  // namespace uf::pipeline
