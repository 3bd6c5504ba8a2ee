#include "viewer/pipeline/stages/accuracy_stage.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "odometry/eval/plots.h"
#include "odometry/io/geo_trajectory_file.h"
#include "odometry/io/trajectory_file.h"

namespace uf::pipeline {

namespace fs = std::filesystem;

GroundTruthCheck EvaluateAgainstGroundTruth(const fs::path& ground_truth, const fs::path& out_folder,
                                            const std::string& estimate_file,
                                            const std::optional<EnuOrigins>& enu, bool gravity_aligned) {
  GroundTruthCheck check;
  // The same steps and defaults as `ultrafusion eval REF EST --align se3` (eval_command.cpp).
  auto reference = ReadTrajectory(ground_truth.string());
  if (!reference) {
    check.note = "ground truth unreadable: " + reference.error();
    return check;
  }
  const std::string estimate_path = (out_folder / estimate_file).string();
  auto estimate = ReadTrajectory(estimate_path);
  if (!estimate) {
    check.note = "estimate unreadable: " + estimate.error();
    return check;
  }
  const EvalOptions options;  // align se3, max_dt 0.01 s, RPE delta 1 frame
  auto result = Evaluate(*reference, *estimate, options);
  if (!result) {
    check.note = "evaluation failed: " + result.error();
    return check;
  }
  const EvalContext context{.reference_path = ground_truth.string(),
                            .estimate_path = estimate_file,
                            .reference_poses = reference->size(),
                            .estimate_poses = estimate->size(),
                            .options = options,
                            .align_name = "se3",
                            .rpe_unit_name = "frames"};
  std::ostringstream table;
  PrintEvalTable(table, context, *result);
  check.table = table.str();
  check.evaluated = true;
  check.ape_rmse_m = result->ape.rmse;
  check.matched_poses = result->estimate.size();
  if (gravity_aligned) {
    EvalOptions yaw = options;
    yaw.align = AlignMode::kYaw;
    if (Expected<EvalResult> yawed = Evaluate(*reference, *estimate, yaw))
      check.yaw_ape_rmse_m = yawed->ape.rmse;
  }
  if (enu) {
    Expected<EnuAccuracy> in_enu = EvaluateInEnu(*reference, enu->truth, *estimate, enu->run);
    if (in_enu)
      check.enu = *in_enu;
    else
      check.enu_note = "no unaligned ENU figures: " + in_enu.error();
  }
  if (Status s = WriteEvalPlots((out_folder / "plots").string(), context, *result); !s.ok()) {
    check.note = "plots not written: " + s.message();
    return check;
  }
  for (const char* plot : {"ape_top_view.png", "ape_over_time.png", "rpe_over_time.png"})
    if (fs::exists(out_folder / "plots" / plot)) check.plots.push_back(std::string("plots/") + plot);
  return check;
}

Expected<EnuAccuracy> EvaluateInEnu(const Trajectory& ground_truth, const GeodeticOrigin& truth_origin,
                                    const Trajectory& trajectory_enu, const GeodeticOrigin& run_origin) {
  Expected<EnuFrame> truth_frame = EnuFrame::Create(truth_origin);
  if (!truth_frame) return truth_frame.status();
  Expected<EnuFrame> run_frame = EnuFrame::Create(run_origin);
  if (!run_frame) return run_frame.status();
  // p_run = EnuFromGeodetic_run(GeodeticFromEnu_truth(p_truth)); the orientation turns with the tangent
  // plane (LocalEnuFromOriginEnu, about 1 deg per 111 km between the origins).
  const Eigen::Matrix3d R_run_truth =
      LocalEnuFromOriginEnu(truth_origin, run_origin.latitude_deg, run_origin.longitude_deg);
  Trajectory truth_in_run = ground_truth;
  for (SE3& pose : truth_in_run.poses)
    pose = SE3(SO3(R_run_truth * pose.rotation()),
               run_frame->EnuFromGeodetic(truth_frame->GeodeticFromEnu(pose.translation())));
  EvalOptions options;
  options.align = AlignMode::kNone;
  Expected<EvalResult> result = Evaluate(truth_in_run, trajectory_enu, options);
  if (!result) return result.status();
  EnuAccuracy enu;
  enu.matched_poses = result->estimate.size();
  double all = 0, horizontal = 0, vertical = 0;
  for (std::size_t i = 0; i < enu.matched_poses; ++i) {
    const Eigen::Vector3d e = result->estimate[i].translation() - result->reference[i].translation();
    all += e.squaredNorm();
    horizontal += e.head<2>().squaredNorm();
    vertical += e.z() * e.z();
  }
  const double n = static_cast<double>(std::max<std::size_t>(enu.matched_poses, 1));
  enu.rmse_m = std::sqrt(all / n);
  enu.horizontal_rmse_m = std::sqrt(horizontal / n);
  enu.vertical_rmse_m = std::sqrt(vertical / n);
  return enu;
}

namespace {

// Without ground truth: trajectory.tum against the fixes.
GroundTruthCheck CheckAgainstGnssTrack(const fs::path& out, const std::optional<Georeference>& georef,
                                       const GnssTrackInput& gnss, StageContext& context) {
  GroundTruthCheck check;
  check.note = "no ground truth beside the dataset";
  Expected<Trajectory> trajectory = ReadTrajectory((out / "trajectory.tum").string());
  Expected<GnssTrackError> track =
      trajectory
          ? CompareWithGnssTrack(*trajectory, gnss.fixes, gnss.T_frame_antenna,
                                 georef ? std::optional(georef->origin) : std::nullopt, gnss.gravity_aligned)
          : Expected<GnssTrackError>(trajectory.status());
  if (!track) {
    check.gnss_track_note = "no comparison with the GNSS track: " + track.error();
    context.SetMessage(check.note + "; " + check.gnss_track_note);
    return check;
  }
  // The top view: the fixes (grey) and the trajectory's antenna coloured by its horizontal error.
  const std::string plot = "plots/gnss_track_top_view.png";
  std::error_code error;
  fs::create_directories(out / "plots", error);
  if (Status s = WriteTopViewPlot((out / plot).string(), track->fixes_enu, track->antenna_enu,
                                  track->horizontal_error_m,
                                  std::string("Trajectory against the GNSS track (") +
                                      (track->aligned ? "fitted" : "georeferenced") + ")",
                                  "horizontal error [m]");
      s.ok()) {
    check.plots.push_back(plot);
    context.AddOutput(plot);
  } else {
    check.gnss_track_note = "plot not written: " + s.message();
  }
  context.SetUnit("fixes");
  context.Progress(track->fixes, track->fixes);
  check.gnss_track = std::move(*track);
  return check;
}

// Reference poses of a sensor S (T_w_S) in trajectory.tum's frame F, T_w_F = T_w_S T_S_F, at trajectory.tum's
// stamps within the reference's span (Trajectory::PoseAt: a sensor's records are rarely taken at the LiDAR's
// instants: KITTI's OXTS runs 12-19 ms behind the scans, 0.2 m at city speed), written to out/reference.tum.
Expected<fs::path> WriteReferenceInOutputFrame(const Trajectory& T_world_sensor, const SE3& T_sensor_output,
                                               const fs::path& out) {
  Expected<Trajectory> estimate = ReadTrajectory((out / "trajectory.tum").string());
  if (!estimate) return estimate.status();
  Trajectory in_output;
  for (const Stamp stamp : estimate->stamps) {
    if (const std::optional<SE3> pose = T_world_sensor.PoseAt(stamp)) {
      in_output.stamps.push_back(stamp);
      in_output.poses.push_back(*pose * T_sensor_output);
    }
  }
  if (in_output.empty()) return Status::Error("no pose of trajectory.tum lies within the reference's span");
  const fs::path path = out / "reference.tum";
  if (Status s = WriteTumTrajectory(path.string(), in_output); !s.ok()) return s;
  return path;
}

// out/reference.tum, when the evaluation needs one, or nullopt (the ground-truth file as it is):
// - a ground-truth file holds poses of the dataset's body frame B (DatasetDescription::ground_truth). When
//   trajectory.tum is in another frame F (LO: the LiDAR, which simulated rigs carry 0.25 m above the IMU), it
//   is taken to F, T_w_F = T_w_B T_F_B^-1: compared as they were, a pose tilted by theta differs by theta
//   times the lever arm (a handheld LiDAR swinging by 10 deg: 4 cm) wherever the estimate is exact;
// - without one, the reader's reference (T_w_S of its stream's sensor) in F: T_S_F = T_B_S^-1 T_F_B^-1.
Expected<std::optional<fs::path>> WriteReference(const DatasetDescription& description, const fs::path& out,
                                                 const SE3& T_output_body) {
  Expected<fs::path> path = Status::Error("no reference");
  if (description.ground_truth) {
    if (T_output_body.matrix().isIdentity(1e-12)) return std::optional<fs::path>();
    Expected<Trajectory> truth = ReadTrajectory(description.ground_truth->string());
    if (!truth) return truth.status();
    path = WriteReferenceInOutputFrame(*truth, T_output_body.inverse(), out);
  } else {
    const ReferenceTrajectory& reference = *description.reference;
    const StreamInfo& sensor = description.streams.at(static_cast<std::size_t>(reference.stream));
    path = WriteReferenceInOutputFrame(
        reference.poses, sensor.T_body_sensor.value_or(SE3()).inverse() * T_output_body.inverse(), out);
  }
  if (!path) return path.status();
  return std::optional<fs::path>(*path);
}

}  // namespace

GroundTruthCheck RunAccuracyStage(const DatasetDescription& description, const fs::path& out,
                                  const std::optional<Georeference>& georef, const GnssTrackInput& gnss,
                                  const SE3& T_output_body, StageContext& context) {
  if (!description.ground_truth && !description.reference)
    return CheckAgainstGnssTrack(out, georef, gnss, context);
  GroundTruthCheck accuracy;
  const Expected<std::optional<fs::path>> reference = WriteReference(description, out, T_output_body);
  if (!reference) {
    accuracy.note = (description.ground_truth ? "ground truth not taken to trajectory.tum's frame: "
                                              : "reference not written: ") +
                    reference.error();
    context.SetMessage("not evaluated: " + accuracy.note);
    return accuracy;
  }
  if (*reference) context.AddOutput("reference.tum");
  const fs::path ground_truth = *reference ? **reference : *description.ground_truth;
  context.SetUnit("poses");
  std::optional<EnuOrigins> enu;
  if (georef && description.ground_truth && description.ground_truth_enu_origin)
    enu = EnuOrigins{*description.ground_truth_enu_origin, georef->origin};
  // The yaw-aligned ATE needs both worlds gravity-aligned: a ground-truth file's is taken to be (the
  // simulator's, EuRoC's), a reader's reference is not (KITTI raw's starts at its first OXTS pose, tilted).
  accuracy = EvaluateAgainstGroundTruth(ground_truth, out, "trajectory.tum", enu,
                                        gnss.gravity_aligned && description.ground_truth.has_value());
  if (!description.ground_truth) accuracy.reference_source = description.reference->source;
  accuracy.ground_truth_moved_to_output_frame = description.ground_truth && *reference;
  if (accuracy.evaluated && georef && !enu)
    accuracy.enu_note = "the ground truth states no ENU origin: no unaligned ENU figures";
  if (!accuracy.evaluated) {
    context.SetMessage("not evaluated: " + accuracy.note);
    return accuracy;
  }
  // The poses evaluated (with --from, the odometry stage did not run here: its keyframe count is 0).
  const auto poses = static_cast<std::int64_t>(accuracy.matched_poses);
  context.Progress(poses, poses);
  for (const std::string& plot : accuracy.plots) context.AddOutput(plot);
  return accuracy;
}

}  // namespace uf::pipeline
