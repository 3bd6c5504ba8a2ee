#include "viewer/pipeline/run/run_pipeline.h"

#include <charconv>
#include <iostream>

#include "odometry/types/printf_text.h"
#include "splat/splat_renderer.h"
#include "viewer/app/config/estimator_config.h"
#include "viewer/app/config/wio_config.h"

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
  summary.dataset = r.dataset.string();
  summary.format = std::string(DatasetFormatName(description.format));
  const OdometryMode core = plan.frames.mode;
  std::vector<int> used;
  if (core != OdometryMode::kWio) used.push_back(plan.sensors.lidar);
  if (core != OdometryMode::kLo) used.push_back(plan.sensors.imu);
  if (plan.mode.wheel) used.push_back(plan.sensors.wheel);
  if (plan.mode.gnss) used.push_back(plan.sensors.gnss);
  if (plan.mode.camera) used.push_back(plan.sensors.camera);
  std::string streams;
  for (int stream : used) streams += (streams.empty() ? "" : ", ") + description.streams[stream].name;
  const bool wheel_factors = plan.mode.wheel && core != OdometryMode::kWio;  // WIO is the wheel's window
  const char* factors = wheel_factors && plan.mode.gnss ? " with wheel and GNSS factors"
                        : wheel_factors                 ? " with wheel factors"
                        : plan.mode.gnss                ? " with GNSS factors"
                                                        : "";
  const char* inertial = !plan.mode.camera ? "wheel-inertial"
                         : plan.mode.wheel ? "visual-wheel-inertial"
                                           : "visual-inertial";
  const char* kind = core == OdometryMode::kLio
                         ? (plan.mode.camera ? "LiDAR-visual-inertial" : "LiDAR-inertial")
                     : core == OdometryMode::kWio ? inertial
                                                  : "LiDAR-only";
  summary.mode = ModeName(plan.mode) + " (" + kind + " odometry" + factors + " on " + streams + ")";
  summary.output_frame = plan.frames.trajectory_frame;
  for (const std::string& note : summary.notes) std::cerr << "ultrafusion: warning: " << note << "\n";
  if (const std::optional<PointTimeSelection>& times = summary.point_times) {
    summary.notes.push_back("point times of " + times->stream + ": " + times->Line());
    std::cerr << "ultrafusion: " << summary.notes.back() << "\n";
  }
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
  // The estimator's section: lo: (and lio:) or wio:; splat: only when splats may be trained.
  summary.config_yaml =
      app::EmitDatasetConfig(r.dataset_config) +
      (core == OdometryMode::kWio ? app::EmitInertialOdometryConfig(plan.wio_config)
                                  : app::EmitLidarOdometryConfig(plan.lo_config)) +
      (r.no_splat || core == OdometryMode::kWio ? "" : app::EmitSplatConfig(r.splat_config));
  summary.repeat_command = RepeatCommand(r, plan.frames, plan.mode);
}

// The options that the chosen mode and the dataset cannot honour: an output frame without the transform
// to it, --from with a mode that makes no map.
Status CheckModeOptions(const RunRequest& r, const DatasetSensors& sensors,
                        const DatasetDescription& description, const EstimatorMode& mode,
                        TrajectoryFrame frame) {
  if (mode.core == OdometryMode::kWio && r.from != RunFrom::kStart)
    return Status::Error(std::string("--from ") + (r.from == RunFrom::kMap ? "map" : "splat") + ": " +
                         ModeName(mode) + " makes no map (it reads no LiDAR)");
  if (frame == EstimatorFrame(mode.core) || sensors.T_imu_lidar) return {};
  const std::string other(Name(EstimatorFrame(mode.core)));
  if (sensors.lidar < 0)
    return Status::Error("--output-frame lidar: " + r.dataset.string() +
                         " has no LiDAR stream; use --output-frame " + other);
  return Status::Error("--output-frame " + std::string(Name(frame)) + ": " + r.dataset.string() +
                       " gives no LiDAR-to-IMU transform (T_body_sensor) for " +
                       description.streams[sensors.lidar].name + "; use --output-frame " + other);
}

// An IMU that samples slower than its configured gap allows (KITTI raw's 10 Hz OXTS against the default
// 0.05 s) would see a gap between every two samples and never initialize: the gap becomes 1.5 sample periods
// of the stream's nominal rate, and the report says so.
void FitImuGapToRate(double& imu_max_gap_s, const DatasetDescription& description, int imu,
                     std::vector<std::string>& notes) {
  if (imu < 0) return;
  const StreamInfo& stream = description.streams[static_cast<std::size_t>(imu)];
  if (!(stream.nominal_rate_hz > 0) || 1.5 / stream.nominal_rate_hz <= imu_max_gap_s) return;
  const double fitted = 1.5 / stream.nominal_rate_hz;
  notes.push_back(PrintfText("imu_max_gap_s raised from %.3f to %.3f s: ", imu_max_gap_s, fitted) +
                  stream.name + PrintfText(" samples at %.1f Hz", stream.nominal_rate_hz));
  imu_max_gap_s = fitted;
}

// The stereo rig's right camera for the camera factors (visual.stereo, and a second camera in the data,
// dataset_sensors.h); the report's notes say which pair.
void ConfigureStereo(const DatasetDescription& description, const DatasetSensors& sensors, bool stereo,
                     std::shared_ptr<const CameraModel>& right, SE3& T_body_right,
                     std::vector<std::string>& notes) {
  if (!stereo || sensors.camera_right < 0) return;
  const StreamInfo& stream = description.streams[static_cast<std::size_t>(sensors.camera_right)];
  right = stream.camera_model;
  T_body_right = *sensors.T_imu_camera_right;
  const double baseline = (sensors.T_imu_camera->inverse() * T_body_right).translation().norm();
  notes.push_back("stereo: " + description.streams[static_cast<std::size_t>(sensors.camera)].name + " with " +
                  stream.name + PrintfText(" (baseline %.3f m)", baseline));
}

// The estimator's configuration from the request's and the dataset's extrinsics. LO and LIO: the body is
// the LiDAR in LO and the IMU in LIO; WIO: the IMU.
void ConfigureEstimator(RunPlan& plan) {
  const RunRequest& r = plan.request;
  const EstimatorMode& mode = plan.mode;
  const DatasetSensors& sensors = plan.sensors;
  // The GNSS lever arm: T_imu_gnss (GNSS needs an inertial core); without an extrinsic, the antenna is
  // taken at the IMU, and the report says so.
  const DatasetDescription& description = plan.stream->description();
  const SE3 T_imu_gnss = sensors.T_imu_gnss.value_or(SE3());
  if (mode.gnss && !sensors.T_imu_gnss)
    plan.summary.notes.push_back("GNSS: " + description.streams[sensors.gnss].name +
                                 " has no T_body_sensor: the antenna is taken at the IMU (no lever arm)");
  if (mode.core == OdometryMode::kWio) {
    plan.wio_config = r.wio_config;
    plan.wio_config.use_wheel = mode.wheel;
    if (mode.wheel) plan.wio_config.T_body_wheel = *sensors.T_imu_wheel;  // ChooseMode checked it
    plan.wio_config.use_camera = mode.camera;
    if (mode.camera) {  // ChooseMode checked both
      plan.wio_config.camera = description.streams[sensors.camera].camera_model;
      plan.wio_config.T_body_camera = *sensors.T_imu_camera;
      ConfigureStereo(description, sensors, plan.wio_config.visual.stereo, plan.wio_config.right_camera,
                      plan.wio_config.T_body_right_camera, plan.summary.notes);
    }
    plan.wio_config.use_gnss = mode.gnss;
    plan.wio_config.T_body_gnss = T_imu_gnss;
    FitImuGapToRate(plan.wio_config.imu_max_gap_s, description, sensors.imu, plan.summary.notes);
    return;
  }
  plan.lo_config = r.lo_config;
  plan.lo_config.use_imu = mode.core == OdometryMode::kLio;
  if (plan.lo_config.use_imu)
    FitImuGapToRate(plan.lo_config.imu_max_gap_s, description, sensors.imu, plan.summary.notes);
  plan.lo_config.T_body_lidar = plan.frames.T_estimator_lidar();
  plan.lo_config.use_wheel = mode.wheel;
  // T_body_wheel: T_imu_wheel in LIO, T_lidar_wheel = T_imu_lidar^-1 T_imu_wheel in LO (ChooseMode checked
  // that both exist).
  if (mode.wheel)
    plan.lo_config.T_body_wheel = mode.core == OdometryMode::kLio
                                      ? *sensors.T_imu_wheel
                                      : sensors.T_imu_lidar->inverse() * *sensors.T_imu_wheel;
  plan.lo_config.use_gnss = mode.gnss;
  if (mode.gnss) plan.lo_config.T_body_gnss = T_imu_gnss;
  plan.lo_config.use_camera = mode.camera;
  if (mode.camera) {  // ChooseMode checked both
    plan.lo_config.camera = description.streams[sensors.camera].camera_model;
    plan.lo_config.T_body_camera = *sensors.T_imu_camera;
    ConfigureStereo(description, sensors, plan.lo_config.visual.stereo, plan.lo_config.right_camera,
                    plan.lo_config.T_body_right_camera, plan.summary.notes);
  }
}

// run --calibrate-online: the calibration branch beside a LIO window (calibration_branch.h).
Status PlanOnlineCalibration(RunPlan& plan) {
  const RunRequest& r = plan.request;
  if (!r.calibrate_online) return {};
  if (plan.frames.mode != OdometryMode::kLio || r.from != RunFrom::kStart)
    return Status::Error("--calibrate-online: needs a LIO run from the start (mode " + ModeName(plan.mode) +
                         (r.from != RunFrom::kStart ? ", --from" : "") + ")");
  if (plan.lo_config.estimate_lidar_translation)  // both would write calibration_estimated.yaml's LiDAR
    return Status::Error(
        "--calibrate-online: not with lio.estimate_lidar_translation (the workers and the window would each "
        "write the LiDAR's calibration); run one, then the other with dataset.calibration_file");
  Expected<std::unique_ptr<CalibrationBranch>> branch =
      CalibrationBranch::Create(r.lo_config, *plan.stream, plan.sensors, r.calibration_hold_s);
  if (!branch) return branch.status();
  plan.calibration = std::move(*branch);
  return {};
}

// Point times whose convention the check chose at the start are checked again after the first rejected
// registration or restart of the local map (point_time_recheck.h); LO and LIO from the start.
Status PlanPointTimeRecheck(RunPlan& plan) {
  const std::optional<PointTimeSelection>& times = plan.summary.point_times;
  if (!times || !times->check || !times->convention || plan.frames.mode == OdometryMode::kWio ||
      plan.request.from != RunFrom::kStart)
    return {};
  Expected<estimator::PointTimeRecheck> recheck =
      estimator::PointTimeRecheck::Create(plan.lo_config, *times->convention);
  if (!recheck) return recheck.status();
  plan.point_time_recheck = std::make_unique<estimator::PointTimeRecheck>(std::move(*recheck));
  return {};
}

}  // namespace

Expected<RunPlan> PlanRun(RunRequest request, PlanErrorKind& kind) {
  kind = PlanErrorKind::kUsage;
  if (Status s = CheckOutputFolder(request); !s.ok()) return s;
  if (!request.no_splat && !request.splat_device.empty())
    if (Expected<std::string> device = splat::FindSplatDevice(request.splat_device); !device)
      return Status::Error("--device: " + device.error());
  RunPlan plan;
  kind = PlanErrorKind::kData;
  // Azimuth-derived point times: the convention (configured, or checked on the first scans) every reader
  // of the run derives them with; config.yaml records it. --from splat reads no scan, WIO none of them.
  if (request.from != RunFrom::kSplat && !(request.mode && request.mode->core == OdometryMode::kWio)) {
    Expected<std::optional<PointTimeSelection>> times =
        SelectPointTimes(request.dataset, request.dataset_config, request.lo_config);
    if (!times) return times.status();
    if (*times && (*times)->convention)
      request.dataset_config.reader.point_time_convention = (*times)->convention;
    plan.summary.point_times = std::move(*times);
  }
  plan.request = std::move(request);
  const RunRequest& r = plan.request;
  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(r.dataset, r.dataset_config.reader);
  if (!opened) return opened.status();
  plan.reader = std::move(*opened);
  Expected<MeasurementStream> stream = MeasurementStream::Create(*plan.reader, r.dataset_config.stream);
  if (!stream) return stream.status();
  plan.stream = std::make_unique<MeasurementStream>(std::move(*stream));
  const DatasetDescription& description = plan.stream->description();
  plan.sensors = FindSensors(description);
  // A mode asked for that the data cannot run is the user's; auto finding nothing to run is the data's.
  kind = r.mode ? PlanErrorKind::kUsage : PlanErrorKind::kData;
  Expected<EstimatorMode> mode = ChooseMode(r.mode, description, plan.sensors, plan.summary.notes);
  if (!mode) return mode.status();
  plan.mode = *mode;
  kind = PlanErrorKind::kUsage;
  const TrajectoryFrame frame = r.output_frame.value_or(EstimatorFrame(mode->core));
  if (Status s = CheckModeOptions(r, plan.sensors, description, *mode, frame); !s.ok()) return s;
  Expected<RunFrames> frames =
      ResolveRunFrames(description, mode->core, frame,
                       r.from == RunFrom::kMap ? MapSource::kTrajectory : MapSource::kOdometry);
  if (!frames) return frames.status();
  plan.frames = *frames;
  ConfigureEstimator(plan);
  Expected<std::unique_ptr<RunEstimator>> odometry =
      CreateRunEstimator(plan.mode, plan.lo_config, plan.wio_config);
  if (!odometry) return odometry.status();
  plan.odometry = std::move(*odometry);
  if (Status s = PlanOnlineCalibration(plan); !s.ok()) return s;
  if (Status s = PlanPointTimeRecheck(plan); !s.ok()) return s;
  if (!r.no_map && r.from != RunFrom::kSplat && mode->core != OdometryMode::kWio) {
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
