#include "viewer/app/run_stages.h"

#include <sstream>

#include "odometry/eval/gnss_georeference.h"
#include "viewer/app/run_map_stage.h"
#include "viewer/app/run_outputs.h"
#include "viewer/app/stage_dataset.h"

namespace uf::app {

namespace fs = std::filesystem;

Status RunDatasetStage(RunState& state, StageContext& context) {
  context.SetUnit("messages");
  Expected<DatasetSummary> summary = SummarizeDataset(
      state.dataset, state.dataset_config, [&](std::int64_t messages) { context.Progress(messages); });
  if (!summary) return summary.status();
  std::ostringstream table;
  PrintDatasetTable(table, *summary);
  state.report.dataset_summary = table.str();
  const auto lidar = static_cast<std::size_t>(state.sensors.lidar);
  if (lidar < summary->streams.size()) state.lidar_scans = summary->streams[lidar].time.count;
  return {};
}

namespace {

// Per-scan processing times of the odometry, in scan order.
struct ScanTimes {
  std::vector<Stamp> stamps;
  std::vector<double> ms;
};

// Moves the keyframes that left the odometry's window into the trajectory (and the mapper), in time order.
Status CollectFinished(RunState& state, ScanTimes& times, std::int64_t& keyframes) {
  for (Keyframe& k : state.odometry->TakeFinished()) {
    ++keyframes;
    Trajectory& trajectory = state.estimated;
    if (!trajectory.stamps.empty() && k.stamp <= trajectory.stamps.back())
      continue;  // keep stamps increasing
    trajectory.stamps.push_back(k.stamp);
    trajectory.poses.push_back(k.T_world_body);
    if (state.mapper) {
      if (Status s = state.mapper->AddKeyframe(std::move(k)); !s.ok()) return s;
      ++state.keyframes_mapped;
    }
  }
  for (const estimator::OdometryStats& scan : state.odometry->TakeProcessedStats()) {
    times.stamps.push_back(scan.stamp);
    times.ms.push_back(scan.solve_ms);
  }
  return {};
}

}  // namespace

Status RunOdometryStage(RunState& state, StageContext& context) {
  context.SetUnit("scans");
  ScanTimes times;
  std::int64_t scans = 0, keyframes = 0;
  const DatasetSensors& sensors = state.sensors;
  while (true) {
    Expected<std::optional<Measurement>> next = state.stream->Next();
    if (!next) return next.status();
    if (!next->has_value()) break;
    Measurement& m = **next;
    Status status;
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == sensors.lidar) {
      status = state.odometry->AddScan(*scan);
      ++scans;
    } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == sensors.imu) {
      status = state.odometry->AddImu(*sample);
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data);
               frame && state.mapper && state.mapper->UsesCamera(m.stream)) {
      state.mapper->AddCameraFrame(m.stream, std::move(*frame));
      continue;
    } else if (const auto* fix = std::get_if<GnssFix>(&m.data); fix && m.stream == sensors.gnss) {
      state.fixes.push_back(*fix);
      continue;
    } else {
      continue;
    }
    if (status.ok()) status = CollectFinished(state, times, keyframes);
    if (!status.ok()) return status;
    context.Progress(scans, state.lidar_scans);
  }
  state.odometry->Finish();
  if (Status s = CollectFinished(state, times, keyframes); !s.ok()) return s;

  RunReport& report = state.report;
  if (state.lio) {
    const std::string init = state.odometry->initialization();
    report.notes.push_back(init.empty() ? "LIO never initialized: the whole run is LiDAR-only (see warnings)"
                                        : "LIO initialized: " + init);
  }
  report.scans = scans;
  report.keyframes = static_cast<std::int64_t>(state.estimated.size());
  report.skipped = scans - keyframes;
  report.timing = SummarizeTimings(times.ms);
  report.reader_warnings = state.stream->warnings();
  report.odometry_warnings = state.odometry->warnings();
  if (state.estimated.empty())
    return Status::Error(state.dataset.string() + ": the odometry produced no pose (" +
                         std::to_string(scans) + " scans, " +
                         std::to_string(report.odometry_warnings.size()) + " warnings)");

  // The trajectory in the requested frame (the body is the LiDAR in LO, the IMU in LIO).
  Trajectory trajectory = state.estimated;
  if (!state.lio && state.output_frame == "imu") trajectory = ToImuFrame(trajectory, *sensors.T_imu_lidar);
  if (state.lio && state.output_frame == "lidar") trajectory = ToLidarFrame(trajectory, *sensors.T_imu_lidar);
  const std::int64_t warnings =
      static_cast<std::int64_t>(report.reader_warnings.size() + report.odometry_warnings.size());
  if (Status s = WriteTrajectoryFiles(state.out, trajectory); !s.ok()) return s;
  if (Status s = WriteTimingJson(state.out / "timing.json", report.timing, report.skipped, warnings); !s.ok())
    return s;
  for (const char* file : {"trajectory.tum", "trajectory_kitti.txt", "timing.json"}) context.AddOutput(file);
  if (!times.ms.empty()) {
    std::error_code error;
    fs::create_directories(state.out / "plots", error);
    if (error) return Status::Error((state.out / "plots").string() + ": cannot create: " + error.message());
    if (Status s = WriteTimingPlot(state.out / "plots/timing_per_scan.png", times.stamps, times.ms); !s.ok())
      return s;
    report.timing_plot = "plots/timing_per_scan.png";
    context.AddOutput(report.timing_plot);
  }
  return {};
}

Status RunAccuracyStage(RunState& state, StageContext& context) {
  context.SetUnit("poses");
  GroundTruthCheck& accuracy = state.report.accuracy;
  accuracy =
      EvaluateAgainstGroundTruth(*state.stream->description().ground_truth, state.out, "trajectory.tum");
  // An evaluation that is not possible (a trajectory too short or straight to align, stamps that do not
  // match) is a finding of the report, not a failure of the run.
  if (!accuracy.evaluated) {
    context.SetMessage("not evaluated: " + accuracy.note);
    return {};
  }
  // The poses evaluated (with --from, the odometry stage did not run here: its keyframe count is 0).
  const auto poses = static_cast<std::int64_t>(accuracy.matched_poses);
  context.Progress(poses, poses);
  for (const std::string& plot : accuracy.plots) context.AddOutput(plot);
  return {};
}

Status RunMapStage(RunState& state, StageContext& context) {
  context.SetUnit("keyframes");
  // The odometry stage inserted the keyframes as they left its window; the last ones wait for Finish.
  if (Status s = state.mapper->Finish(); !s.ok()) return s;
  context.Progress(state.keyframes_mapped, state.keyframes_mapped);
  const int gnss = state.sensors.gnss;
  const std::optional<SE3> T_body_gnss =
      gnss < 0 ? std::nullopt
               : state.stream->description().streams[static_cast<std::size_t>(gnss)].T_body_sensor;
  const GnssGeoreference found =
      GeoreferenceFromGnss(state.estimated, state.fixes, T_body_gnss, state.T_estimator_body, state.lio);
  if (!found.note.empty()) state.report.notes.push_back(found.note);
  state.georef = std::nullopt;
  if (found.alignment)
    state.georef = mapping::MapGeoreference{found.alignment->origin, found.alignment->T_enu_world};
  Expected<std::vector<std::string>> files = SaveRunMap(state.out, *state.mapper, state.georef, state.report);
  if (!files) return files.status();
  for (const std::string& file : *files) context.AddOutput(file);
  return {};
}

Status RunExportsStage(RunState& state, StageContext& context) {
  context.SetUnit("files");
  Expected<std::vector<std::string>> files =
      WriteRunMapExports(state.out, *state.mapper, state.georef, state.mesh, state.report);
  if (!files) return files.status();
  for (const std::string& file : *files) context.AddOutput(file);
  context.Progress(static_cast<std::int64_t>(files->size()), static_cast<std::int64_t>(files->size()));
  return {};
}

}  // namespace uf::app
