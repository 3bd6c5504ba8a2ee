#include "viewer/pipeline/stages/odometry_files.h"

#include <algorithm>
#include <filesystem>

#include "odometry/eval/series_plot.h"
#include "odometry/io/geo_trajectory_file.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// T_enu_world applied to every pose: T_enu_F = T_enu_world T_world_F.
Trajectory InEnu(Trajectory trajectory, const SE3& T_enu_world) {
  for (SE3& pose : trajectory.poses) pose = T_enu_world * pose;
  return trajectory;
}

// Each pose with the alignment of the moment it left the window (the poses before the alignment started
// with the first one): the wheel-inertial window's world is held by nothing absolute, its heading drifts
// against ENU and the alignment follows it. (With a LiDAR map the map holds the world, the alignment
// converges, and one transform keeps the trajectory and the map rigidly together: InEnu.)
Trajectory InEnuPerPose(Trajectory trajectory, const SegmentedVector<std::optional<SE3>>& T_enu_world_at_pose,
                        const SE3& T_enu_world_final) {
  std::optional<SE3> first;
  for (const std::optional<SE3>& T : T_enu_world_at_pose)
    if (T && !first) first = T;
  for (std::size_t i = 0; i < trajectory.poses.size(); ++i) {
    const std::optional<SE3>& T = i < T_enu_world_at_pose.size() ? T_enu_world_at_pose[i] : std::nullopt;
    trajectory.poses[i] = (T ? *T : first.value_or(T_enu_world_final)) * trajectory.poses[i];
  }
  return trajectory;
}

// trajectory_wgs84.csv and trajectory.geojson of the ENU trajectory.
Status WriteGeoTrajectory(const std::filesystem::path& folder, const Trajectory& enu,
                          const Georeference& georef, StageContext& context) {
  Expected<EnuFrame> frame = EnuFrame::Create(georef.origin);
  if (!frame) return frame.status();
  if (Status s = WriteWgs84TrajectoryCsv((folder / "trajectory_wgs84.csv").string(), enu, *frame); !s.ok())
    return s;
  context.AddOutput("trajectory_wgs84.csv");
  if (enu.size() < 2) return {};  // a LineString needs two positions
  if (Status s = WriteTrajectoryGeoJson((folder / "trajectory.geojson").string(), enu, *frame); !s.ok())
    return s;
  context.AddOutput("trajectory.geojson");
  return {};
}

// V modes: the landmarks per step (node or scan: mean, and the fewest once the first landmark formed), their
// mean reprojection error, and plots/visual_landmarks.png (landmarks per step over time).
Status WriteVisualSummary(const SegmentedVector<StepTime>& steps, const std::filesystem::path& out,
                          OdometrySummary& summary, StageContext& context) {
  if (steps.empty()) return {};
  std::vector<double> seconds, landmarks;
  double reprojection = 0;
  int with_landmarks = 0;
  for (const StepTime& step : steps) {
    seconds.push_back(ToSeconds(step.stamp - steps[0].stamp));
    landmarks.push_back(step.landmarks);
    if (step.landmarks > 0) {
      reprojection += step.reprojection_px;
      ++with_landmarks;
      summary.visual.fewest_landmarks = summary.visual.fewest_landmarks < 0
                                            ? step.landmarks
                                            : std::min(summary.visual.fewest_landmarks, step.landmarks);
    }
    summary.visual.mean_landmarks += step.landmarks / static_cast<double>(steps.size());
  }
  summary.visual.steps_with_landmarks = with_landmarks;
  summary.visual.mean_reprojection_px = with_landmarks > 0 ? reprojection / with_landmarks : 0;
  summary.visual.plot = "plots/visual_landmarks.png";
  if (Status s =
          WriteSeriesPlot((out / summary.visual.plot).string(), seconds, landmarks, "landmarks", std::nullopt,
                          "Landmarks in the window after each " + summary.step + "'s solve",
                          "time since the first " + summary.step + " (s)", "landmarks");
      !s.ok())
    return s;
  context.AddOutput(summary.visual.plot);
  return {};
}

}  // namespace

// trajectory.tum, trajectory_kitti.txt (in ENU, with the geographic files, when the estimator georeferenced
// the run), timing.json and the timing plot.
Status WriteOdometryFiles(const OdometryStageInput& in, const OdometryStageOutput& out,
                          OdometryCollected& collected, OdometrySummary& summary, StageContext& context) {
  const std::int64_t warnings =
      static_cast<std::int64_t>(summary.reader_warnings.size() + summary.odometry_warnings.size());
  Trajectory written = out.frames.OutputTrajectory(out.estimated);
  if (out.georef) {
    written = out.frames.mode == OdometryMode::kWio
                  ? InEnuPerPose(std::move(written), collected.T_enu_world_at_pose, out.georef->T_enu_world)
                  : InEnu(std::move(written), out.georef->T_enu_world);
    if (Status s = WriteGeoTrajectory(in.out, written, *out.georef, context); !s.ok()) return s;
  }
  if (Status s = WriteTrajectoryFiles(in.out, written); !s.ok()) return s;
  if (Status s = WriteTimingJson(in.out / "timing.json", summary.timing, summary.skipped, warnings,
                                 summary.step, summary.stage_means);
      !s.ok())
    return s;
  for (const char* file : {"trajectory.tum", "trajectory_kitti.txt", "timing.json"}) context.AddOutput(file);
  if (out.frames.mode != OdometryMode::kWio || !collected.scored.empty()) {
    const std::vector<ScoredKeyframe> scored = std::move(collected.scored).TakeVector();
    Expected<ReliabilityFiles> written = WriteReliabilityFiles(in.out, scored);
    if (!written) return written.status();
    for (const std::string& file : written->files) context.AddOutput(file);
    summary.reliability_plot = written->lidar_plot;
    summary.wheel_reliability_plot = written->wheel_plot;
    summary.gnss_reliability_plot = written->gnss_plot;
    summary.imu_reliability_plot = written->imu_plot;
    summary.camera_reliability_plot = written->camera_plot;
    summary.lidar_degenerate = DegenerateSpans(scored, kDegenerateReported);
    summary.wheel_suppressed = SuppressedWheelSpans(scored);
    summary.imu_clipped = ClippedImuSpans(scored);
    summary.camera_suppressed = SuppressedCameraSpans(scored);
    double imu_scores = 0;
    double gnss_scores = 0;
    for (const ScoredKeyframe& k : scored) {
      summary.lidar_scored += k.lidar.has_value();
      summary.wheel_scored += k.wheel.has_value();
      summary.camera_scored += static_cast<std::int64_t>(k.camera.size());
      if (k.imu) {
        ++summary.imu_scored;
        imu_scores += k.imu->score;
      }
      for (const GnssCheck& fix : k.gnss) {
        ++summary.gnss_scored;
        summary.gnss_rejected += !fix.active;
        gnss_scores += fix.score;
      }
    }
    if (summary.gnss_scored > 0)
      summary.gnss_mean_score = gnss_scores / static_cast<double>(summary.gnss_scored);
    if (summary.imu_scored > 0) summary.imu_mean_score = imu_scores / static_cast<double>(summary.imu_scored);
  }
  if (collected.ms.empty()) return {};
  std::error_code error;
  fs::create_directories(in.out / "plots", error);
  if (error) return Status::Error((in.out / "plots").string() + ": cannot create: " + error.message());
  if (Status s = WriteVisualSummary(collected.visual, in.out, summary, context); !s.ok()) return s;
  const std::vector<ImuStateRow> states = std::move(collected.imu_states).TakeVector();
  Expected<ImuStateFiles> state_files = WriteImuStateFiles(in.out, states);
  if (!state_files) return state_files.status();
  for (const std::string& file : state_files->files) context.AddOutput(file);
  summary.imu_states = static_cast<std::int64_t>(states.size());
  summary.imu_accel_bias_plot = state_files->accel_bias_plot;
  summary.imu_gyro_bias_plot = state_files->gyro_bias_plot;
  summary.lidar_translation_plot = state_files->lidar_translation_plot;
  const std::string plot = "plots/timing_per_" + summary.step + ".png";
  if (Status s = WriteTimingPlot(in.out / plot, std::move(collected.stamps).TakeVector(),
                                 std::move(collected.ms).TakeVector(), summary.step);
      !s.ok())
    return s;
  summary.timing_plot = plot;
  context.AddOutput(summary.timing_plot);
  return {};
}

}  // namespace uf::pipeline
