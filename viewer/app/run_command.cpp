#include "viewer/app/run_command.h"

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "odometry/io/dataset_reader.h"
#include "viewer/app/estimator_config.h"
#include "viewer/app/exit_codes.h"
#include "viewer/app/pipeline_stages.h"
#include "viewer/app/report_html.h"
#include "viewer/app/run_folder.h"
#include "viewer/app/run_map_stage.h"
#include "viewer/app/run_outputs.h"
#include "viewer/app/run_splat_stage.h"
#include "viewer/app/run_stages.h"
#include "viewer/app/splat_config.h"
#include "viewer/app/splat_run_inputs.h"
#include "viewer/app/stage_map_from_trajectory.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;

struct RunArguments {
  std::string dataset, out, config, mode = "auto", output_frame;  // output_frame "": the mode's body
  std::string from;  // "map" / "splat": re-run from that stage on the outputs of an earlier run in --out
  bool no_map = false, no_splat = false, no_mesh = false;
  double map_voxel_m = 0.05;
};

// "/imu/data (imu), velodyne (lidar)": the streams a dataset has, for messages.
std::string StreamList(const DatasetDescription& description) {
  std::string list;
  for (const StreamInfo& s : description.streams)
    list += (list.empty() ? "" : ", ") + s.name + " (" + std::string(SensorKindName(s.kind)) + ")";
  return list.empty() ? "none" : list;
}

// --mode auto|lo|lio against what the dataset has: true for LIO. LIO needs an IMU stream and the LiDAR's
// extrinsic; auto falls back to LO (with a note) without them, --mode lio is an error.
Expected<bool> ChooseLio(const RunArguments& a, const DatasetDescription& description,
                         const DatasetSensors& sensors, std::vector<std::string>& notes) {
  if (a.mode == "lo") return false;
  std::string missing;
  if (sensors.imu < 0)
    missing = "no IMU stream";
  else if (!sensors.T_imu_lidar)
    missing = "no LiDAR-to-IMU transform (T_body_sensor of " + description.streams[sensors.lidar].name + ")";
  if (missing.empty()) return true;
  if (a.mode == "lio")
    return Status::Error("--mode lio: " + a.dataset + " has " + missing +
                         " (streams: " + StreamList(description) + ")");
  notes.push_back("--mode auto: " + missing + ", ran LO");
  return false;
}

// The command line that repeats the run: the resolved mode and every option that is not in config.yaml.
std::string RepeatCommand(const RunArguments& a, const RunState& state) {
  char voxel[32] = {};
  std::to_chars(voxel, voxel + sizeof(voxel) - 1, a.map_voxel_m);  // shortest text that reads back exactly
  return "ultrafusion run " + fs::absolute(a.dataset).string() + " --config config.yaml --mode " +
         (state.lio ? "lio" : "lo") + " --output-frame " + state.output_frame + " --map-voxel " + voxel +
         (a.no_map ? " --no-map" : "") + (a.no_mesh ? " --no-mesh" : "") + (a.no_splat ? " --no-splat" : "") +
         " --out NEW_FOLDER";
}

// Everything resolved before a file is written: a failure here leaves no output folder behind. Returns
// the exit code of a failure, nothing when the stages can run.
std::optional<int> Prepare(const RunArguments& a, RunState& state) {
  estimator::LidarOdometryConfig lo_config;
  if (!a.config.empty()) {
    Expected<DatasetConfig> dataset = LoadDatasetConfig(a.config);
    if (!dataset) return ReportUsageError(dataset.status());
    Expected<estimator::LidarOdometryConfig> lo = LoadLidarOdometryConfig(a.config);
    if (!lo) return ReportUsageError(lo.status());
    Expected<SplatConfig> splat = LoadSplatConfig(a.config);
    if (!splat) return ReportUsageError(splat.status());
    state.dataset_config = *dataset;
    lo_config = *lo;
    state.splat_config = *splat;
  }
  std::error_code error;
  if (!a.from.empty()) {
    if (a.out.empty() || !fs::exists(fs::path(a.out) / "trajectory.tum", error))
      return ReportUsageError(
          Status::Error("--from " + a.from + ": needs --out, an earlier run's folder with " +
                        "trajectory.tum" + (a.out.empty() ? "" : " (" + a.out + " has none)")));
    if (a.no_map)
      return ReportUsageError(Status::Error("--from " + a.from + " and --no-map: nothing would run"));
    if (a.from == "splat" && a.no_splat)
      return ReportUsageError(Status::Error("--from splat and --no-splat: nothing would run"));
    if (a.from == "splat" && !fs::exists(fs::path(a.out) / mapping::kMapFileName, error))
      return ReportUsageError(Status::Error("--from splat: " + a.out + " has no map.vdb to seed the splats"));
  } else if (!a.out.empty() && fs::exists(a.out, error) &&
             !(fs::is_directory(a.out, error) && fs::is_empty(a.out, error))) {
    return ReportUsageError(
        Status::Error(a.out + ": exists and is not an empty folder; run writes a new one"));
  }

  state.dataset = a.dataset;
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(a.dataset, state.dataset_config.reader);
  if (!opened) return ReportError(opened.status());
  state.reader = std::move(*opened);
  Expected<MeasurementStream> stream = MeasurementStream::Create(*state.reader, state.dataset_config.stream);
  if (!stream) return ReportError(stream.status());
  state.stream.emplace(std::move(*stream));
  const DatasetDescription& description = state.stream->description();
  state.sensors = FindSensors(description);
  const DatasetSensors& sensors = state.sensors;
  if (sensors.lidar < 0)
    return ReportError(Status::Error(
        a.dataset + ": no LiDAR stream, which LO and LIO need (streams: " + StreamList(description) + ")"));

  RunReport& report = state.report;
  Expected<bool> lio = ChooseLio(a, description, sensors, report.notes);
  if (!lio) return ReportError(lio.status());
  state.lio = *lio;
  const std::string& lidar_name = description.streams[sensors.lidar].name;
  report.dataset = a.dataset;
  report.format = std::string(DatasetFormatName(description.format));
  report.mode = *lio ? "lio (LiDAR-inertial odometry on " + lidar_name + " and " +
                           description.streams[sensors.imu].name + ")"
                     : "lo (LiDAR-only odometry on " + lidar_name + ")";
  state.output_frame = a.output_frame.empty() ? (*lio ? "imu" : "lidar") : a.output_frame;
  report.output_frame = state.output_frame;
  for (const std::string& note : report.notes) std::cerr << "ultrafusion: warning: " << note << "\n";
  if (a.no_splat) report.notes.push_back("--no-splat: no splats trained");
  if (a.no_map) report.notes.push_back("--no-map: no map written");
  if (state.output_frame == "imu" && !sensors.T_imu_lidar)
    return ReportUsageError(Status::Error("--output-frame imu: " + a.dataset +
                                          " gives no LiDAR-to-IMU transform (T_body_sensor) for " +
                                          lidar_name + "; use --output-frame lidar"));
  // The body is the LiDAR in LO and the IMU in LIO.
  lo_config.use_imu = *lio;
  lo_config.T_body_lidar = *lio ? *sensors.T_imu_lidar : SE3();
  Expected<estimator::LidarOdometry> odometry = estimator::LidarOdometry::Create(lo_config);
  if (!odometry) return ReportUsageError(odometry.status());
  state.odometry.emplace(std::move(*odometry));
  state.T_estimator_body = EstimatorFromBody(description, sensors.lidar, sensors.imu, *lio);
  state.mesh = !a.no_mesh;
  state.min_range_m = lo_config.min_range_m;
  state.max_range_m = lo_config.max_range_m;
  if (a.from == "splat")
    report.notes.push_back(
        "--from splat: the splats are trained on map.vdb and trajectory.tum of the earlier "
        "run in this folder");
  if (a.from == "map") {
    report.notes.push_back(
        "--from map: the trajectory is trajectory.tum of the earlier run in this folder, the "
        "map made from the dataset's scans deskewed with it; the odometry's figures are in "
        "timing.json");
    if (fs::exists(fs::path(a.out) / "plots/timing_per_scan.png", error))
      report.timing_plot = "plots/timing_per_scan.png";
  }
  if (!a.no_map && a.from != "splat") {
    mapping::KeyframeMapperOptions options;
    options.map.voxel_size_m = a.map_voxel_m;
    Expected<mapping::KeyframeMapper> created =
        mapping::KeyframeMapper::Create(options, description, state.T_estimator_body);
    if (!created) return ReportUsageError(created.status());
    state.mapper.emplace(std::move(*created));
  }
  report.config_yaml = EmitDatasetConfig(state.dataset_config) + EmitLidarOdometryConfig(lo_config) +
                       (a.no_splat ? "" : EmitSplatConfig(state.splat_config));
  report.repeat_command = RepeatCommand(a, state);
  return std::nullopt;
}

// --out DIR (new or empty), else a new runs/<UTC time>/ under the current folder with runs/latest on it.
Expected<fs::path> CreateOutputFolder(const RunArguments& a) {
  if (a.out.empty()) {
    Expected<fs::path> folder = CreateVersionedRunFolder("runs", std::chrono::system_clock::now());
    if (!folder) return folder.status();
    if (Status s = UpdateLatestLink("runs", *folder); !s.ok()) return s;
    return folder;
  }
  std::error_code error;
  fs::create_directories(a.out, error);
  if (error) return Status::Error(a.out + ": cannot create the folder: " + error.message());
  return fs::path(a.out);
}

// The stages in order; with --from map or --from splat the stages before it reuse the earlier run's files.
std::vector<Stage> RunStageList(const RunArguments& a, RunState& state) {
  auto bind = [&state](Status (*run)(RunState&, StageContext&)) {
    return [&state, run](StageContext& context) { return run(state, context); };
  };
  const DatasetDescription& description = state.stream->description();
  const bool truth = description.ground_truth.has_value();
  const bool from_map = a.from == "map", from_splat = a.from == "splat";
  const std::string reuse = from_map     ? "--from map: trajectory.tum of the earlier run"
                            : from_splat ? "--from splat: the earlier run's outputs"
                                         : "";
  const std::string no_splat = a.no_splat ? "--no-splat"
                               : a.no_map ? "--no-map: no map to seed the splats from"
                                          : SplatSkipReason(description, state.output_frame);
  return {
      {"dataset", "the dataset", reuse, bind(RunDatasetStage)},
      {"odometry", state.lio ? "LiDAR and IMU streams" : "LiDAR stream", reuse, bind(RunOdometryStage)},
      from_map ? Stage{"map", "trajectory.tum, the dataset's scans", "", bind(RunMapFromTrajectoryStage)}
               : Stage{"map", "keyframes (odometry)", a.no_map ? "--no-map" : reuse, bind(RunMapStage)},
      {"exports", "map (map stage)",
       a.no_map     ? "--no-map: no map to export"
       : from_splat ? reuse
                    : "",
       bind(RunExportsStage)},
      {"splat", "map.vdb, trajectory.tum, camera images", no_splat, bind(RunSplatStage)},
      {"views", "splats (splat stage)", no_splat.empty() ? "" : "no splats", bind(RunViewsStage)},
      {"accuracy", "trajectory.tum, ground truth", truth ? "" : "no ground truth beside the dataset",
       bind(RunAccuracyStage)},
  };
}

// run.json: what `ultrafusion splat RUN_DIR` needs to read the dataset again and place its images. --from
// splat keeps the earlier run's (its trajectory and map are the ones trained on).
Status WriteRunInfo(const RunArguments& a, const RunState& state) {
  if (a.from == "splat" && ReadRunJson(state.out).ok()) return {};
  RunInfo info;
  info.dataset = fs::absolute(a.dataset).string();
  info.output_frame = state.output_frame;
  info.mode = state.lio ? "lio" : "lo";
  info.map_from = a.from == "map" ? "trajectory" : "odometry";
  return WriteRunJson(state.out, info);
}

// report.md and report.html; written whether or not a stage failed.
Status WriteReports(const fs::path& out, const RunReport& report) {
  const std::string markdown = FormatRunReport(report);
  if (Status s = WriteTextFileAtomically(out / "report.md", markdown); !s.ok()) return s;
  return WriteTextFileAtomically(out / "report.html", MarkdownReportToHtml(markdown, out, "ultrafusion run"));
}

void PrintSummary(const fs::path& out, const RunState& state, const PipelineResult& result) {
  const RunReport& report = state.report;
  if (report.scans > 0)
    std::printf("run: %s, %lld scans, %lld poses, %.1f ms/scan mean (%.1f p95), %lld warnings\n",
                report.mode.c_str(), static_cast<long long>(report.scans),
                static_cast<long long>(report.keyframes), report.timing.mean, report.timing.p95,
                static_cast<long long>(report.reader_warnings.size() + report.odometry_warnings.size()));
  std::printf("%s", FormatStageTable(result.stages).c_str());
  if (report.accuracy.evaluated)
    std::printf("  ATE (SE3-aligned RMSE): %.4f m\n", report.accuracy.ape_rmse_m);
  if (report.map) std::printf("  map: %s\n", report.map->summary.c_str());
  if (state.splat) {
    const SplatMetrics& m = state.splat->metrics;
    std::printf(
        "  splats: %zu Gaussians, held-out PSNR %.2f dB, SSIM %.3f (%zu views), %d iterations at %.2f/s on "
        "%s\n",
        m.gaussians, m.test.psnr, m.test.ssim, m.views_test, m.iterations, m.iterations_per_s(),
        m.device.c_str());
  }
  std::printf("  wrote %s (report.md, report.html, config.yaml and the outputs above)\n", out.c_str());
}

int RunRun(const RunArguments& a) {
  RunState state;
  if (std::optional<int> code = Prepare(a, state)) return *code;
  Expected<fs::path> out = CreateOutputFolder(a);
  if (!out) return ReportError(out.status());
  state.out = *out;
  const std::string config = "# The resolved configuration of this run. Repeat it exactly with\n#   " +
                             state.report.repeat_command + "\n" + state.report.config_yaml;
  if (Status s = WriteTextFileAtomically(state.out / "config.yaml", config); !s.ok()) return ReportError(s);
  if (Status s = WriteRunInfo(a, state); !s.ok()) return ReportError(s);

  ProgressLine progress("run");
  const PipelineResult result = RunStages(RunStageList(a, state), progress, "run");
  state.report.stages = result.stages;
  for (const StageRecord& stage : result.stages) state.report.wall_seconds += stage.seconds;
  const Status written = WriteReports(state.out, state.report);
  PrintSummary(state.out, state, result);
  if (const StageRecord* failed = result.failure())
    return ReportError(Status::Error("the " + failed->name + " stage failed: " + failed->message + " (see " +
                                     (state.out / "report.md").string() + ")"));
  if (!written.ok()) return ReportError(written);
  return kExitOk;
}

}  // namespace

Subcommand AddRunCommand(CLI::App& app) {
  auto a = std::make_shared<RunArguments>();
  CLI::App* run = app.add_subcommand("run", "Run the odometry over a dataset: trajectory, timing and report");
  run->add_option("DATASET", a->dataset, "ROS1 .bag file, or a KITTI-style, EuRoC or ultrafusion folder")
      ->required();
  run->add_option("--out", a->out,
                  "Output folder (new or empty); default: a new runs/<UTC time>/ with runs/latest");
  run->add_option("--config", a->config,
                  "YAML file with dataset:, lo:, lio: and splat: sections (see configs/kitti.yaml, "
                  "configs/run-sim.yaml, "
                  "configs/splat.yaml)")
      ->check(CLI::ExistingFile);
  run->add_option(
         "--mode", a->mode,
         "auto: LIO with an IMU and the LiDAR's extrinsic, else LO; lo: LiDAR only; lio: LiDAR + IMU")
      ->check(CLI::IsMember({"auto", "lo", "lio"}))
      ->capture_default_str();
  run->add_option("--output-frame", a->output_frame,
                  "Frame of the written trajectory: lidar or imu (needs the LiDAR's T_body_sensor); default: "
                  "lidar for LO, imu for LIO")
      ->check(CLI::IsMember({"lidar", "imu"}));
  run->add_option("--from", a->from,
                  "Re-run from this stage on an earlier run's outputs in --out: map (reuses trajectory.tum, "
                  "re-reads the scans; give the options of that run, e.g. the command in its config.yaml) or "
                  "splat (reuses map.vdb and trajectory.tum, re-reads the images)")
      ->check(CLI::IsMember({"map", "splat"}));
  run->add_flag("--no-map", a->no_map, "No map: no map.vdb, map.voxels, map.ply, map.las, map.glb");
  run->add_option("--map-voxel", a->map_voxel_m, "Voxel size of the colour map, m")
      ->check(CLI::Range(0.001, 100.0))
      ->capture_default_str();
  run->add_flag("--no-mesh", a->no_mesh, "No surface mesh in map.glb (points only; faster on big maps)");
  run->add_flag("--no-splat", a->no_splat, "No splats: no splats.ply, splats.glb, metrics.json, views/");
  return {run, [a] { return RunRun(*a); }};
}

}  // namespace uf::app
