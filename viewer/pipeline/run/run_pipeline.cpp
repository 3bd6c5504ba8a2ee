#include "viewer/pipeline/run/run_pipeline.h"

#include <charconv>
#include <iostream>

#include "viewer/app/config/estimator_config.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// The command line that repeats the run: the resolved mode and every option that is not in config.yaml.
std::string RepeatCommand(const RunRequest& r, const RunFrames& frames, const EstimatorMode& mode) {
  char voxel[32] = {};
  std::to_chars(voxel, voxel + sizeof(voxel) - 1, r.map_voxel_m);  // shortest text that reads back exactly
  return "ultrafusion run " + fs::absolute(r.dataset).string() + " --config config.yaml --mode " +
         ModeName(mode) + " --output-frame " + std::string(Name(frames.trajectory_frame)) + " --map-voxel " +
         voxel + (r.no_map ? " --no-map" : "") + (r.no_mesh ? " --no-mesh" : "") +
         (r.no_splat ? " --no-splat" : "") + " --out NEW_FOLDER";
}

// The --from and --out checks: the folder an earlier run left, or a new or empty one.
Status CheckOutputFolder(const RunRequest& r) {
  std::error_code error;
  const std::string out = r.out.string();
  if (r.from != RunFrom::kStart) {
    const std::string from = r.from == RunFrom::kMap ? "map" : "splat";
    if (out.empty() || !fs::exists(r.out / "trajectory.tum", error))
      return Status::Error("--from " + from + ": needs --out, an earlier run's folder with trajectory.tum" +
                           (out.empty() ? "" : " (" + out + " has none)"));
    if (r.no_map) return Status::Error("--from " + from + " and --no-map: nothing would run");
    if (r.from == RunFrom::kSplat && r.no_splat)
      return Status::Error("--from splat and --no-splat: nothing would run");
    if (r.from == RunFrom::kSplat && !fs::exists(r.out / mapping::kMapFileName, error))
      return Status::Error("--from splat: " + out + " has no map.vdb to seed the splats");
  } else if (!out.empty() && fs::exists(r.out, error) &&
             !(fs::is_directory(r.out, error) && fs::is_empty(r.out, error))) {
    return Status::Error(out + ": exists and is not an empty folder; run writes a new one");
  }
  return {};
}

// The summary's notes on the request, its description of the mode, the resolved config and the command that
// repeats the run.
void DescribeRun(RunPlan& plan) {
  const RunRequest& r = plan.request;
  RunSummary& summary = plan.summary;
  const DatasetDescription& description = plan.stream->description();
  const std::string& lidar = description.streams[plan.sensors.lidar].name;
  summary.dataset = r.dataset.string();
  summary.format = std::string(DatasetFormatName(description.format));
  std::string streams = lidar;
  if (plan.frames.mode == OdometryMode::kLio) streams += ", " + description.streams[plan.sensors.imu].name;
  if (plan.mode.wheel) streams += ", " + description.streams[plan.sensors.wheel].name;
  if (plan.mode.gnss) streams += ", " + description.streams[plan.sensors.gnss].name;
  const char* factors = plan.mode.wheel && plan.mode.gnss ? " with wheel and GNSS factors"
                        : plan.mode.wheel                 ? " with wheel factors"
                        : plan.mode.gnss                  ? " with GNSS factors"
                                                          : "";
  summary.mode = ModeName(plan.mode) + " (" +
                 (plan.frames.mode == OdometryMode::kLio ? "LiDAR-inertial" : "LiDAR-only") + " odometry" +
                 factors + " on " + streams + ")";
  summary.output_frame = plan.frames.trajectory_frame;
  for (const std::string& note : summary.notes) std::cerr << "ultrafusion: warning: " << note << "\n";
  if (r.no_splat) summary.notes.push_back("--no-splat: no splats trained");
  if (r.no_map) summary.notes.push_back("--no-map: no map written");
  if (r.from == RunFrom::kSplat)
    summary.notes.push_back(
        "--from splat: the splats are trained on map.vdb and trajectory.tum of the earlier run in "
        "this folder");
  if (r.from == RunFrom::kMap) {
    summary.notes.push_back(
        "--from map: the trajectory is trajectory.tum of the earlier run in this folder, the map made "
        "from the dataset's scans deskewed with it; the odometry's figures are in timing.json");
    std::error_code error;
    if (fs::exists(r.out / "plots/timing_per_scan.png", error))
      summary.odometry.timing_plot = "plots/timing_per_scan.png";
  }
  summary.config_yaml = app::EmitDatasetConfig(r.dataset_config) +
                        app::EmitLidarOdometryConfig(plan.lo_config) +
                        (r.no_splat ? "" : app::EmitSplatConfig(r.splat_config));
  summary.repeat_command = RepeatCommand(r, plan.frames, plan.mode);
}

}  // namespace

Expected<RunPlan> PlanRun(RunRequest request, PlanErrorKind& kind) {
  kind = PlanErrorKind::kUsage;
  if (Status s = CheckOutputFolder(request); !s.ok()) return s;
  RunPlan plan;
  plan.request = std::move(request);
  const RunRequest& r = plan.request;
  kind = PlanErrorKind::kData;
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(r.dataset, r.dataset_config.reader);
  if (!opened) return opened.status();
  plan.reader = std::move(*opened);
  Expected<MeasurementStream> stream = MeasurementStream::Create(*plan.reader, r.dataset_config.stream);
  if (!stream) return stream.status();
  plan.stream = std::make_unique<MeasurementStream>(std::move(*stream));
  const DatasetDescription& description = plan.stream->description();
  plan.sensors = FindSensors(description);
  if (plan.sensors.lidar < 0)
    return Status::Error(r.dataset.string() + ": no LiDAR stream, which LO and LIO need (streams: " +
                         StreamList(description) + ")");
  kind = PlanErrorKind::kUsage;
  Expected<EstimatorMode> mode = ChooseMode(r.mode, description, plan.sensors, plan.summary.notes);
  if (!mode) return mode.status();
  plan.mode = *mode;
  const TrajectoryFrame frame = r.output_frame.value_or(EstimatorFrame(mode->core));
  if (frame == TrajectoryFrame::kImu && !plan.sensors.T_imu_lidar)
    return Status::Error("--output-frame imu: " + r.dataset.string() +
                         " gives no LiDAR-to-IMU transform (T_body_sensor) for " +
                         description.streams[plan.sensors.lidar].name + "; use --output-frame lidar");
  Expected<RunFrames> frames =
      ResolveRunFrames(description, mode->core, frame,
                       r.from == RunFrom::kMap ? MapSource::kTrajectory : MapSource::kOdometry);
  if (!frames) return frames.status();
  plan.frames = *frames;
  // The body is the LiDAR in LO and the IMU in LIO.
  plan.lo_config = r.lo_config;
  plan.lo_config.use_imu = mode->core == OdometryMode::kLio;
  plan.lo_config.T_body_lidar = plan.frames.T_estimator_lidar();
  plan.lo_config.use_wheel = mode->wheel;
  // T_body_wheel: T_imu_wheel in LIO, T_lidar_wheel = T_imu_lidar^-1 T_imu_wheel in LO (ChooseMode checked
  // that both exist).
  if (mode->wheel)
    plan.lo_config.T_body_wheel = mode->core == OdometryMode::kLio
                                      ? *plan.sensors.T_imu_wheel
                                      : plan.sensors.T_imu_lidar->inverse() * *plan.sensors.T_imu_wheel;
  // The GNSS lever arm: T_imu_gnss (GNSS needs the inertial core); without an extrinsic, the antenna is
  // taken at the IMU, and the report says so.
  plan.lo_config.use_gnss = mode->gnss;
  if (mode->gnss) {
    plan.lo_config.T_body_gnss = plan.sensors.T_imu_gnss.value_or(SE3());
    if (!plan.sensors.T_imu_gnss)
      plan.summary.notes.push_back("GNSS: " + description.streams[plan.sensors.gnss].name +
                                   " has no T_body_sensor: the antenna is taken at the IMU (no lever arm)");
  }
  Expected<estimator::LidarOdometry> odometry = estimator::LidarOdometry::Create(plan.lo_config);
  if (!odometry) return odometry.status();
  plan.odometry = std::make_unique<estimator::LidarOdometry>(std::move(*odometry));
  if (!r.no_map && r.from != RunFrom::kSplat) {
    mapping::KeyframeMapperOptions options;
    options.map.voxel_size_m = r.map_voxel_m;
    Expected<mapping::KeyframeMapper> mapper =
        mapping::KeyframeMapper::Create(options, description, plan.frames.T_estimator_body);
    if (!mapper) return mapper.status();
    plan.mapper = std::make_unique<mapping::KeyframeMapper>(std::move(*mapper));
  }
  DescribeRun(plan);
  return plan;
}

}  // namespace uf::pipeline
