#include "viewer/app/run_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/app/dataset_config.h"
#include "viewer/app/estimator_config.h"
#include "viewer/app/exit_codes.h"
#include "viewer/app/keyframe_mapper.h"
#include "viewer/app/run_map_stage.h"
#include "viewer/app/run_outputs.h"
#include "viewer/app/run_report.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RunArguments {
  std::string dataset, out, config, mode = "auto", output_frame;  // output_frame "": the mode's body
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

// On a terminal, one line on stderr rewritten at most every half second: scans done, rate, ms per scan.
class ScanProgress {
 public:
  explicit ScanProgress(std::string mode) : mode_(std::move(mode)) {}
  void Update(std::int64_t scans, double ms_total) {
    if (!terminal_ || Clock::now() - last_ < std::chrono::milliseconds(500)) return;
    last_ = Clock::now();
    const double seconds = std::chrono::duration<double>(last_ - start_).count();
    std::fprintf(stderr, "\rrun: %s %lld scans, %.1f scans/s, %.1f ms/scan\033[K", mode_.c_str(),
                 static_cast<long long>(scans), seconds > 0 ? scans / seconds : 0.0,
                 scans > 0 ? ms_total / scans : 0.0);
    shown_ = true;
  }
  ~ScanProgress() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  std::string mode_;
  bool terminal_ = isatty(STDERR_FILENO);
  bool shown_ = false;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

// Removes the output folder again when the run failed before writing anything into it.
int FailAndClean(const fs::path& out, int code) {
  std::error_code error;
  if (fs::is_directory(out, error) && fs::is_empty(out, error)) fs::remove(out, error);
  return code;
}

// The sensors `run` uses: the first LiDAR stream, the first IMU stream and the LiDAR-to-IMU transform.
struct RunSensors {
  int lidar = -1, imu = -1, gnss = -1;
  std::optional<SE3> T_imu_lidar;
};

RunSensors FindSensors(const DatasetDescription& description) {
  RunSensors sensors;
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    const SensorKind kind = description.streams[s].kind;
    if (kind == SensorKind::kLidar && sensors.lidar < 0) sensors.lidar = static_cast<int>(s);
    if (kind == SensorKind::kImu && sensors.imu < 0) sensors.imu = static_cast<int>(s);
    if (kind == SensorKind::kGnss && sensors.gnss < 0) sensors.gnss = static_cast<int>(s);
  }
  if (sensors.lidar >= 0) sensors.T_imu_lidar = ImuFromLidar(description, sensors.lidar);
  return sensors;
}

// --mode auto|lo|lio against what the dataset has: true for LIO. LIO needs an IMU stream and the LiDAR's
// extrinsic; auto falls back to LO (with a note) without them, --mode lio is an error.
Expected<bool> ChooseLio(const RunArguments& a, const DatasetDescription& description,
                         const RunSensors& sensors, std::vector<std::string>& notes) {
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

int RunRun(const RunArguments& a) {
  DatasetConfig dataset_config;
  estimator::LidarOdometryConfig lo_config;
  if (!a.config.empty()) {
    Expected<DatasetConfig> dataset = LoadDatasetConfig(a.config);
    if (!dataset) return ReportUsageError(dataset.status());
    Expected<estimator::LidarOdometryConfig> lo = LoadLidarOdometryConfig(a.config);
    if (!lo) return ReportUsageError(lo.status());
    dataset_config = *dataset;
    lo_config = *lo;
  }
  std::error_code error;
  if (fs::exists(a.out, error) && !(fs::is_directory(a.out, error) && fs::is_empty(a.out, error)))
    return ReportUsageError(
        Status::Error(a.out + ": exists and is not an empty folder; run writes a new one"));

  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(a.dataset, dataset_config.reader);
  if (!opened) return ReportError(opened.status());
  Expected<MeasurementStream> stream = MeasurementStream::Create(**opened, dataset_config.stream);
  if (!stream) return ReportError(stream.status());
  const DatasetDescription& description = stream->description();
  const RunSensors sensors = FindSensors(description);
  if (sensors.lidar < 0)
    return ReportError(Status::Error(
        a.dataset + ": no LiDAR stream, which LO and LIO need (streams: " + StreamList(description) + ")"));

  RunReport report;
  Expected<bool> lio = ChooseLio(a, description, sensors, report.notes);
  if (!lio) return ReportError(lio.status());
  const std::string& lidar_name = description.streams[sensors.lidar].name;
  report.dataset = a.dataset;
  report.format = std::string(DatasetFormatName(description.format));
  report.mode = *lio ? "lio (LiDAR-inertial odometry on " + lidar_name + " and " +
                           description.streams[sensors.imu].name + ")"
                     : "lo (LiDAR-only odometry on " + lidar_name + ")";
  report.output_frame = a.output_frame.empty() ? (*lio ? "imu" : "lidar") : a.output_frame;
  for (const std::string& note : report.notes) std::cerr << "ultrafusion: warning: " << note << "\n";
  if (a.no_splat) report.notes.push_back("--no-splat: accepted; no splatting stage exists yet");
  if (report.output_frame == "imu" && !sensors.T_imu_lidar)
    return ReportUsageError(Status::Error("--output-frame imu: " + a.dataset +
                                          " gives no LiDAR-to-IMU transform (T_body_sensor) for " +
                                          lidar_name + "; use --output-frame lidar"));
  // The body is the LiDAR in LO and the IMU in LIO.
  lo_config.use_imu = *lio;
  lo_config.T_body_lidar = *lio ? *sensors.T_imu_lidar : SE3();
  Expected<estimator::LidarOdometry> odometry = estimator::LidarOdometry::Create(lo_config);
  if (!odometry) return ReportUsageError(odometry.status());
  const SE3 T_estimator_body = EstimatorFromBody(description, sensors.lidar, sensors.imu, *lio);
  std::optional<KeyframeMapper> mapper;
  if (!a.no_map) {
    KeyframeMapperOptions options;
    options.map.voxel_size_m = a.map_voxel_m;
    Expected<KeyframeMapper> created = KeyframeMapper::Create(options, description, T_estimator_body);
    if (!created) return ReportUsageError(created.status());
    mapper.emplace(std::move(*created));
  }

  fs::create_directories(a.out, error);
  if (error) return ReportError(Status::Error(a.out + ": cannot create the folder: " + error.message()));
  const Clock::time_point start = Clock::now();
  std::vector<double> ms_per_scan;  // of the scans processed (skipped ones cost next to nothing)
  std::int64_t scans_read = 0;
  Trajectory trajectory;  // T_world_body at each keyframe (LO: world = the first LiDAR pose)
  std::int64_t keyframes = 0;
  std::vector<GnssFix> fixes;  // for the map's georeference
  double ms_total = 0;
  {
    ScanProgress progress(*lio ? "lio" : "lo");
    // Keyframes leave the window in time order: their poses go into the trajectory, the keyframes (with
    // their deskewed scans) into the map.
    auto collect = [&]() -> Status {
      for (Keyframe& k : odometry->TakeFinished()) {
        ++keyframes;
        if (!trajectory.stamps.empty() && k.stamp <= trajectory.stamps.back())
          continue;  // keep stamps increasing
        trajectory.stamps.push_back(k.stamp);
        trajectory.poses.push_back(k.T_world_body);
        if (mapper)
          if (Status s = mapper->AddKeyframe(std::move(k)); !s.ok()) return s;
      }
      for (const estimator::OdometryStats& scan : odometry->TakeProcessedStats()) {
        ms_per_scan.push_back(scan.solve_ms);
        ms_total += scan.solve_ms;
      }
      return {};
    };
    while (true) {
      Expected<std::optional<Measurement>> next = stream->Next();
      if (!next) return FailAndClean(a.out, ReportError(next.status()));
      if (!next->has_value()) break;
      const Measurement& m = **next;
      Status status;
      if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == sensors.lidar) {
        status = odometry->AddScan(*scan);
        ++scans_read;
      } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == sensors.imu) {
        status = odometry->AddImu(*sample);
      } else if (auto* frame = std::get_if<CameraFrame>(&(*next)->data);
                 frame && mapper && mapper->UsesCamera((*next)->stream)) {
        mapper->AddCameraFrame((*next)->stream, std::move(*frame));
        continue;
      } else if (const auto* fix = std::get_if<GnssFix>(&m.data); fix && m.stream == sensors.gnss) {
        fixes.push_back(*fix);
        continue;
      } else {
        continue;
      }
      if (status.ok()) status = collect();
      if (!status.ok()) return FailAndClean(a.out, ReportError(status));
      progress.Update(scans_read, ms_total);
    }
    odometry->Finish();
    Status status = collect();
    if (status.ok() && mapper) status = mapper->Finish();
    if (!status.ok()) return FailAndClean(a.out, ReportError(status));
  }
  if (*lio) {
    const std::string init = odometry->initialization();
    report.notes.push_back(init.empty() ? "LIO never initialized: the whole run is LiDAR-only (see warnings)"
                                        : "LIO initialized: " + init);
  }
  const Trajectory estimated = trajectory;  // in the estimator's body frame, for the georeference
  if (!*lio && report.output_frame == "imu") trajectory = ToImuFrame(trajectory, *sensors.T_imu_lidar);
  if (*lio && report.output_frame == "lidar") trajectory = ToLidarFrame(trajectory, *sensors.T_imu_lidar);
  if (trajectory.empty())
    return FailAndClean(
        a.out, ReportError(Status::Error(a.dataset + ": the odometry produced no pose (" +
                                         std::to_string(scans_read) + " scans, " +
                                         std::to_string(odometry->warnings().size()) + " warnings)")));

  report.scans = scans_read;
  report.keyframes = static_cast<std::int64_t>(trajectory.size());
  report.skipped = report.scans - keyframes;
  report.timing = SummarizeTimings(ms_per_scan);
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  report.reader_warnings = stream->warnings();
  report.odometry_warnings = odometry->warnings();
  report.config_yaml = EmitDatasetConfig(dataset_config) + EmitLidarOdometryConfig(lo_config);
  const fs::path out(a.out);
  const std::int64_t warnings =
      static_cast<std::int64_t>(report.reader_warnings.size() + report.odometry_warnings.size());
  if (Status s = WriteTrajectoryFiles(out, trajectory); !s.ok()) return ReportError(s);
  if (Status s = WriteTimingJson(out / "timing.json", report.timing, report.skipped, warnings); !s.ok())
    return ReportError(s);
  if (Status s = WriteTextFileAtomically(out / "config.yaml", report.config_yaml); !s.ok())
    return ReportError(s);
  if (mapper) {
    const std::optional<mapping::MapGeoreference> georef = GeoreferenceFromGnss(
        description, sensors.gnss, T_estimator_body, estimated, fixes, *lio, report.notes);
    if (Status s = WriteRunMap(out, *mapper, georef, !a.no_mesh, report); !s.ok()) return ReportError(s);
  } else {
    report.notes.push_back("--no-map: no map written");
  }
  if (description.ground_truth)
    report.accuracy = EvaluateAgainstGroundTruth(*description.ground_truth, out, "trajectory.tum");
  else
    report.accuracy.note = "No ground truth found beside the dataset: no accuracy figures.";
  if (Status s = WriteTextFileAtomically(out / "report.md", FormatRunReport(report)); !s.ok())
    return ReportError(s);

  std::printf("run: %s, %lld scans, %lld poses, %.1f ms/scan mean (%.1f p95), %lld warnings\n",
              report.mode.c_str(), static_cast<long long>(report.scans),
              static_cast<long long>(report.keyframes), report.timing.mean, report.timing.p95,
              static_cast<long long>(warnings));
  if (report.accuracy.evaluated)
    std::printf("  ATE (SE3-aligned RMSE): %.4f m\n", report.accuracy.ape_rmse_m);
  if (report.map) std::printf("  map: %s\n", report.map->summary.c_str());
  std::printf("  wrote %s: trajectory.tum, trajectory_kitti.txt, timing.json, config.yaml, report.md%s%s\n",
              a.out.c_str(), report.accuracy.plots.empty() ? "" : ", plots/",
              report.map ? (", " + report.map->files).c_str() : "");
  return kExitOk;
}

}  // namespace

Subcommand AddRunCommand(CLI::App& app) {
  auto a = std::make_shared<RunArguments>();
  CLI::App* run = app.add_subcommand("run", "Run the odometry over a dataset: trajectory, timing and report");
  run->add_option("DATASET", a->dataset, "ROS1 .bag file, or a KITTI-style, EuRoC or ultrafusion folder")
      ->required();
  run->add_option("--out", a->out, "Output folder (new or empty)")->required();
  run->add_option(
         "--config", a->config,
         "YAML file with dataset:, lo: and lio: sections (see configs/kitti.yaml, configs/run-sim.yaml)")
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
  run->add_flag("--no-map", a->no_map, "No map: no map.vdb, map.voxels, map.ply, map.las, map.glb");
  run->add_option("--map-voxel", a->map_voxel_m, "Voxel size of the colour map, m")
      ->check(CLI::Range(0.001, 100.0))
      ->capture_default_str();
  run->add_flag("--no-mesh", a->no_mesh, "No surface mesh in map.glb (points only; faster on big maps)");
  run->add_flag("--no-splat", a->no_splat, "No splatting (accepted; a no-op until the splat stage exists)");
  return {run, [a] { return RunRun(*a); }};
}

}  // namespace uf::app
