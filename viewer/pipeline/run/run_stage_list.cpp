// The stages of `ultrafusion run` in order, each wired to the plan and to the outputs of the stages before
// it (run_pipeline.h), and the run around them: output folder, config.yaml, run.json, cameras.yaml, the
// summary.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <numbers>

#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run/run_calibration_estimate.h"
#include "viewer/pipeline/run/run_cameras.h"
#include "viewer/pipeline/run/run_pipeline.h"
#include "viewer/pipeline/run/run_record.h"
#include "viewer/pipeline/run/run_tracks.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/run_folder.h"
#include "viewer/pipeline/stages/exports_stage.h"
#include "viewer/pipeline/stages/map_from_trajectory_stage.h"
#include "viewer/pipeline/stages/splat_stage.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// --out DIR (new or empty), else a new runs/<UTC time>/ under the current folder with runs/latest on it.
Expected<fs::path> CreateOutputFolder(const RunRequest& r) {
  if (r.out.empty()) {
    Expected<fs::path> folder = CreateVersionedRunFolder("runs", std::chrono::system_clock::now());
    if (!folder) return folder.status();
    if (Status s = UpdateLatestLink("runs", *folder); !s.ok()) return s;
    return folder;
  }
  std::error_code error;
  fs::create_directories(r.out, error);
  if (error) return Status::Error(r.out.string() + ": cannot create the folder: " + error.message());
  return r.out;
}

// The stages' outputs, each written by its own stage only and read by the later ones.
struct StageOutputs {
  std::optional<DatasetStageOutput> dataset;
  std::optional<OdometryStageOutput> odometry;
  std::optional<MapFromTrajectoryOutput> from_trajectory;
  std::optional<MapStageOutput> map;
  std::optional<MapExportResult> exports;
  std::optional<SplatStageOutput> splat;
  std::optional<std::string> views;
  std::optional<GroundTruthCheck> accuracy;
};

// Runs `stage` and keeps its output in `slot`.
template <typename T>
Status Keep(std::optional<T>& slot, Expected<T> output) {
  if (!output) return output.status();
  slot = std::move(*output);
  return {};
}

// What the odometry stage reads: "LiDAR, IMU and camera streams".
std::string OdometryInput(const EstimatorMode& mode) {
  std::vector<std::string> streams;
  if (mode.core != OdometryMode::kWio) streams.push_back("LiDAR");
  if (mode.core != OdometryMode::kLo) streams.push_back("IMU");
  if (mode.wheel) streams.push_back("wheel");
  if (mode.camera) streams.push_back("camera");
  if (mode.gnss) streams.push_back("GNSS");
  std::string text;
  for (std::size_t i = 0; i < streams.size(); ++i)
    text += (i == 0 ? "" : i + 1 == streams.size() ? " and " : ", ") + streams[i];
  return text + (streams.size() > 1 ? " streams" : " stream");
}

// The report's line on the camera's factors: counts, t_d, the extrinsic when estimated, the map's depths.
std::string VisualNote(const RunPlan& plan, const estimator::SensorFactorStats& factors) {
  const estimator::VisualFactorConfig& visual = plan.visual_config();
  std::string note = PrintfText(
                         "visual factors: %.0f reprojections added, %.0f tracks long enough that never "
                         "triangulated, %.0f landmarks dropped as outliers; camera time offset t_d %.4f s",
                         factors.visual.added, factors.visual.skipped, factors.visual.rejected,
                         factors.camera_time_offset_s) +
                     (visual.estimate_time_offset ? " (estimated)" : " (fixed)");
  if (factors.camera_time_offset_estimates > 0)
    note += PrintfText(
        ": the median of the window's %.0f estimates weighted by their features' image motion, interquartile "
        "range %.1f ms, the last %.4f s",
        factors.camera_time_offset_estimates, 1e3 * factors.camera_time_offset_iqr_s,
        factors.camera_time_offset_window_s);
  if (factors.camera_extrinsic) {
    const SE3 moved = plan.T_imu_camera().inverse() * *factors.camera_extrinsic;
    note += PrintfText("; camera extrinsic estimated: %.3f deg and %.4f m from the given one",
                       moved.so3().angle() * 180 / std::numbers::pi, moved.translation().norm());
  }
  if (plan.frames.mode == OdometryMode::kLio)
    note += "; " + std::to_string(factors.visual_map_depths) +
            " landmarks took their depth from the LiDAR map (" + std::to_string(factors.visual_map_planes) +
            " held on its plane)";
  if (plan.stereo_stream() >= 0)
    note += PrintfText(
        "; stereo: %.0f frame pairs matched, %.0f landmarks took their depth from a pair, %.0f "
        "of the reprojections are the right camera's",
        factors.stereo_pairs, factors.stereo_depths, factors.stereo_factors);
  return note;
}

// The report's line on the LiDAR extrinsic's translation estimated in the window.
std::string LidarTranslationNote(const RunPlan& plan, const estimator::SensorFactorStats& factors) {
  const Eigen::Vector3d t = factors.lidar_extrinsic->translation();
  const Eigen::Vector3d moved = t - plan.lo_config.T_body_lidar.translation();
  return PrintfText("LiDAR extrinsic translation estimated: (%.4f, %.4f, %.4f) m, %.4f m from the given one",
                    t.x(), t.y(), t.z(), moved.norm()) +
         PrintfText("; it moved in %.0f of %.0f window solves", factors.lidar_translation_free_solves,
                    factors.lidar_translation_solves) +
         " (in the others the window's orientations did not spread enough about every axis to show it)";
}

// The LiDAR map's ring gate as the run used it (docs/METHOD.md "Voxel-hash map and PCA planes").
std::string RingGateNote(const RunPlan& plan, int rings) {
  const bool automatic = plan.lo_config.map.min_plane_rings == 0;
  const std::string setting =
      "lo.map.min_plane_rings " + (automatic ? std::string("auto: ") : std::to_string(rings));
  if (rings == 1)
    return "LiDAR map: planes from blocks of any number of LiDAR rings (" + setting +
           (automatic
                ? "the scans' rings are unknown or fewer than 32; with a sparse LiDAR outdoors, 2 keeps "
                  "the map from tilting: docs/METHOD.md \"Voxel-hash map and PCA planes\")"
                : ")");
  return "LiDAR map: planes only from blocks spanning >= " + std::to_string(rings) + " LiDAR rings (" +
         setting + (automatic ? "a LiDAR of 32 rings or more)" : ")");
}

// The map stage on the odometry's keyframes, or (--from map) on the earlier trajectory and the scans.
Status RunMap(RunPlan& plan, const fs::path& out, StageOutputs& o, StageContext& context) {
  MapStageInput in;
  in.mapper = plan.mapper.get();
  in.description = &plan.stream->description();
  in.gnss_stream = plan.sensors.gnss;
  in.frames = plan.frames;
  in.out = out;
  if (o.odometry) in.estimator_georef = o.odometry->georef;
  if (plan.request.from == RunFrom::kMap) {
    const MapFromTrajectoryInput from{.stream = plan.stream.get(),
                                      .mapper = plan.mapper.get(),
                                      .sensors = plan.sensors,
                                      .frames = plan.frames,
                                      .min_range_m = plan.lo_config.min_range_m,
                                      .max_range_m = plan.lo_config.max_range_m,
                                      .out = out};
    if (Status s = Keep(o.from_trajectory, RunMapFromTrajectory(from, context)); !s.ok()) return s;
    in.estimated = &o.from_trajectory->estimated;
    in.fixes = o.from_trajectory->fixes;
    in.keyframes_mapped = o.from_trajectory->keyframes_mapped;
  } else {
    in.estimated = &o.odometry->estimated;
    in.fixes = o.odometry->fixes;
    in.keyframes_mapped = o.odometry->keyframes_mapped;
  }
  return Keep(o.map, RunMapStage(in, context));
}

std::vector<Stage> RunStageList(RunPlan& plan, const fs::path& out, StageOutputs& o) {
  const RunRequest& r = plan.request;
  const DatasetDescription& description = plan.stream->description();
  const bool from_map = r.from == RunFrom::kMap, from_splat = r.from == RunFrom::kSplat;
  const std::string reuse = from_map     ? "--from map: trajectory.tum of the earlier run"
                            : from_splat ? "--from splat: the earlier run's outputs"
                                         : "";
  const OdometryMode core = plan.frames.mode;
  const std::string no_lidar =
      core == OdometryMode::kWio ? ModeName(plan.mode) + ": no LiDAR keyframes to map" : "";
  const std::string no_splat = r.no_splat          ? "--no-splat"
                               : r.no_map          ? "--no-map: no map to seed the splats from"
                               : !no_lidar.empty() ? no_lidar
                                                   : SplatSkipReason(description, plan.frames.T_output_body);
  const int paced_stream = PacedStream(plan.sensors, core);
  auto dataset = [&](StageContext& c) {
    return Keep(o.dataset, RunDatasetStage(r.dataset, r.dataset_config, paced_stream, c));
  };
  auto odometry = [&](StageContext& c) {
    const OdometryStageInput in{.stream = plan.stream.get(),
                                .odometry = plan.odometry.get(),
                                .mapper = plan.mapper.get(),
                                .sensors = plan.sensors,
                                .frames = plan.frames,
                                .gnss_factors = plan.mode.gnss,
                                .camera_factors = plan.mode.camera,
                                .stereo_stream = plan.stereo_stream(),
                                .overlay_every = r.overlay_every,
                                .min_track_length = plan.visual_config().tracker.min_track_length,
                                .calibration = plan.calibration.get(),
                                .point_time_recheck = plan.point_time_recheck.get(),
                                .paced_messages = o.dataset ? o.dataset->paced_messages : 0,
                                .out = out};
    if (Status s = Keep(o.odometry, RunOdometryStage(in, c)); !s.ok()) return s;
    if (const auto& recheck = o.odometry->summary.point_time_recheck)
      std::cerr << "ultrafusion: point times of " << plan.summary.point_times->stream << ": "
                << recheck->Line() << "\n";
    if (Status s = WriteRunTracks(plan, *o.odometry, out, c); !s.ok()) return s;
    if (Status s = WriteWindowCalibrationEstimate(plan, *o.odometry, out, c); !s.ok()) return s;
    const std::optional<OnlineCalibrationSummary>& calibration = o.odometry->summary.online_calibration;
    if (!o.odometry->georef && !(calibration && calibration->rotation_applied_at)) return Status();
    // trajectory.tum is in ENU: run.json gets the map's new T_M_W, which the splat stage reads; or the
    // run applied a new LiDAR extrinsic.
    plan.frames = o.odometry->frames;
    return WriteRunRecord(out, {fs::absolute(r.dataset).string(), plan.frames});
  };
  auto map = [&](StageContext& c) { return RunMap(plan, out, o, c); };
  auto exports = [&](StageContext& c) {
    const ExportsStageInput in{
        .mapper = plan.mapper.get(), .georef = o.map->georef, .mesh = !r.no_mesh, .out = out};
    return Keep(o.exports, RunExportsStage(in, c));
  };
  auto splat = [&](StageContext& c) {
    return Keep(o.splat, RunSplatStage(out, r.splat_config, r.splat_device, c));
  };
  auto views = [&](StageContext& c) {
    return Keep(o.views, RunViewsStage(out, o.splat->result, r.splat_config.training.render.background,
                                       r.splat_device, c));
  };
  auto accuracy = [&](StageContext& c) {
    const std::vector<GnssFix>* fixes = o.odometry          ? &o.odometry->fixes
                                        : o.from_trajectory ? &o.from_trajectory->fixes
                                                            : nullptr;
    GnssTrackInput gnss;
    gnss.gravity_aligned = core != OdometryMode::kLo;
    if (fixes) gnss.fixes = *fixes;
    if (plan.sensors.gnss >= 0)
      gnss.T_frame_antenna =
          plan.frames.T_output_body * description.streams[plan.sensors.gnss].T_body_sensor.value_or(SE3());
    o.accuracy = RunAccuracyStage(description, out, o.odometry ? o.odometry->georef : std::nullopt, gnss,
                                  plan.frames.T_output_body, c);
    return Status();
  };
  const std::string odometry_input = OdometryInput(plan.mode);
  return {
      {"dataset", "the dataset", reuse, dataset},
      {"odometry", odometry_input, reuse, odometry},
      {"map", from_map ? "trajectory.tum, the dataset's scans" : "keyframes (odometry)",
       r.no_map ? "--no-map" : (!no_lidar.empty() ? no_lidar : (from_map ? "" : reuse)), map},
      {"exports", "map (map stage)",
       r.no_map            ? "--no-map: no map to export"
       : !no_lidar.empty() ? "no map to export"
       : from_splat        ? reuse
                           : "",
       exports},
      {"splat", "map.vdb, trajectory.tum, camera images", no_splat, splat},
      {"views", "splats (splat stage)", no_splat.empty() ? "" : "no splats", views},
      {"accuracy", "trajectory.tum, ground truth (else the GNSS fixes)",
       description.ground_truth || description.reference || plan.sensors.gnss >= 0 ? ""
                                                          : "no ground truth beside the dataset, no GNSS",
       accuracy},
  };
}

// The summary of the run from what the stages left.
void Summarize(const RunPlan& plan, StageOutputs& o, RunSummary& summary) {
  if (o.dataset) {
    summary.dataset_summary = std::move(o.dataset->summary);
    summary.dataset_summary->point_times = summary.point_times;
  }
  if (o.odometry) {
    summary.odometry = std::move(o.odometry->summary);
    const std::string& init = summary.odometry.initialization;
    if (plan.frames.mode == OdometryMode::kLio)
      summary.notes.push_back(init.empty()
                                  ? "LIO never initialized: the whole run is LiDAR-only (see warnings)"
                                  : "LIO initialized: " + init);
    if (plan.frames.mode == OdometryMode::kWio)
      summary.notes.push_back(init.empty() ? "WIO never initialized: no pose (see warnings)"
                                           : "WIO initialized: " + init);
    const estimator::SensorFactorStats& factors = summary.odometry.sensor_factors;
    if (factors.lidar_plane_rings > 0) summary.notes.push_back(RingGateNote(plan, factors.lidar_plane_rings));
    if (const auto& recheck = summary.odometry.point_time_recheck)
      summary.notes.push_back("point times of " + summary.point_times->stream + ": " + recheck->Line() +
                              (recheck->switched_from
                                   ? " (config.yaml keeps the convention the run started with; "
                                     "dataset.point_time_convention sets this one from the start)"
                                   : ""));
    if (plan.mode.wheel) {
      char scale[32];
      std::snprintf(scale, sizeof(scale), "%.4f", factors.wheel_scale);
      summary.notes.push_back("wheel factors: " + std::to_string(factors.wheel.added) + " added, " +
                              std::to_string(factors.wheel.skipped) +
                              " skipped (no wheel samples over the interval), " +
                              std::to_string(factors.wheel.rejected) +
                              " left out by the reliability scheduling (the wheel disagreed with the IMU); "
                              "estimated wheel scale " +
                              scale + "; " + std::to_string(factors.wheel_at_rest) +
                              " intervals held at rest (the wheels read no motion: the stationary branch); " +
                              std::to_string(factors.lidar_translations_to_wheel) +
                              " scans left a weakly held translation to the wheel (reliability scheduling)");
    }
    if (plan.mode.camera) summary.notes.push_back(VisualNote(plan, factors));
    if (factors.lidar_extrinsic) summary.notes.push_back(LidarTranslationNote(plan, factors));
    if (plan.mode.gnss)
      summary.notes.push_back("GNSS factors: " + std::to_string(factors.gnss.added) + " added (" +
                              std::to_string(factors.gnss_horizontal_only) +
                              " of them horizontally: their height failed the integrity check), " +
                              std::to_string(factors.gnss.rejected) + " rejected by the integrity check (" +
                              std::to_string(factors.gnss_held_out) +
                              " of them held out by its step guard: multipath), " +
                              std::to_string(factors.gnss.skipped) +
                              " fixes skipped (screening, time order, no node near); ENU alignment " +
                              (factors.gnss_alignment.empty() ? "never tried" : factors.gnss_alignment));
    if (plan.mode.gnss && factors.gnss_innovations.tested > 0) {
      const estimator::SensorFactorStats::Innovations& innovations = factors.gnss_innovations;
      char text[512];
      std::snprintf(
          text, sizeof(text),
          "GNSS innovations (%d fixes tested before their factor): horizontal median %.3f m, 95 %% "
          "%.3f m; mean d^2 %.2f (3 for errors as large as the test assumes: lower, it is cautious; "
          "higher, the fixes or the prediction are worse than their sigmas)",
          innovations.tested, innovations.horizontal_median_m, innovations.horizontal_p95_m,
          innovations.mean_d2);
      summary.notes.push_back(text);
    }
  }
  if (o.from_trajectory) {
    for (std::string& note : o.from_trajectory->notes) summary.notes.push_back(std::move(note));
    summary.odometry.scans = o.from_trajectory->scans;
    summary.odometry.keyframes = static_cast<std::int64_t>(o.from_trajectory->estimated.size());
  }
  if (o.map) {
    for (std::string& note : o.map->notes) summary.notes.push_back(std::move(note));
    summary.map = std::move(o.map->map);
    if (o.exports) AddExportsToSummary(*o.exports, !plan.request.no_mesh, *summary.map);
  }
  if (o.splat) {
    for (std::string& note : o.splat->notes) summary.notes.push_back(std::move(note));
    summary.splat = std::move(o.splat->result);
  }
  if (o.views) summary.splat_views = *o.views;
  if (o.accuracy) summary.accuracy = std::move(*o.accuracy);
}

}  // namespace

Expected<RunSummary> RunPipeline(RunPlan& plan, fs::path& out) {
  const RunRequest& r = plan.request;
  RunSummary& summary = plan.summary;
  Expected<fs::path> folder = CreateOutputFolder(r);
  if (!folder) return folder.status();
  out = *folder;
  const std::string config = "# The resolved configuration of this run. Repeat it exactly with\n#   " +
                             summary.repeat_command + "\n" + summary.config_yaml;
  if (Status s = WriteTextFileAtomically(out / "config.yaml", config); !s.ok()) return s;
  // run.json: --from splat keeps the earlier run's (its trajectory and map are the ones trained on).
  if (r.from != RunFrom::kSplat || !ReadRunRecord(out).ok())
    if (Status s = WriteRunRecord(out, {fs::absolute(r.dataset).string(), plan.frames}); !s.ok()) return s;
  // cameras.yaml: where the cameras sit and how they project, for `render RUN_DIR --stamps`.
  std::vector<Stamp> time_offsets;
  for (std::size_t stream = 0; stream < plan.stream->description().streams.size(); ++stream)
    time_offsets.push_back(plan.stream->time_offset(static_cast<int>(stream)));
  if (Status s = WriteRunCameras(out, PlacedCameras(plan.stream->description(), time_offsets)); !s.ok())
    return s;

  ProgressLine progress("run");
  StageOutputs outputs;
  const PipelineResult result = RunStages(RunStageList(plan, out, outputs), progress, "run");
  summary.stages = result.stages;
  for (const StageRecord& stage : result.stages) summary.wall_seconds += stage.seconds;
  Summarize(plan, outputs, summary);
  return std::move(summary);
}

}  // namespace uf::pipeline
