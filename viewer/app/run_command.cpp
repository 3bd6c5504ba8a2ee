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
#include "viewer/app/run_outputs.h"
#include "viewer/app/run_report.h"

namespace uf::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RunArguments {
  std::string dataset, out, config, mode = "auto", output_frame = "lidar";
  bool no_map = false, no_splat = false;
};

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

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
  void Update(std::int64_t scans, double ms_total) {
    if (!terminal_ || Clock::now() - last_ < std::chrono::milliseconds(500)) return;
    last_ = Clock::now();
    const double seconds = std::chrono::duration<double>(last_ - start_).count();
    std::fprintf(stderr, "\rrun: lo %lld scans, %.1f scans/s, %.1f ms/scan\033[K",
                 static_cast<long long>(scans), seconds > 0 ? scans / seconds : 0.0,
                 scans > 0 ? ms_total / scans : 0.0);
    shown_ = true;
  }
  ~ScanProgress() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
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

int RunRun(const RunArguments& a) {
  if (a.mode == "lio")
    return ReportUsageError(Status::Error(
        "--mode lio: LiDAR-inertial odometry (LIO) is not built yet; use --mode lo (or --mode auto, which "
        "falls back to LO)"));
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
  lo_config.T_body_lidar = SE3();  // LO: the body is the LiDAR
  std::error_code error;
  if (fs::exists(a.out, error) && !(fs::is_directory(a.out, error) && fs::is_empty(a.out, error)))
    return ReportUsageError(
        Status::Error(a.out + ": exists and is not an empty folder; run writes a new one"));

  Expected<std::unique_ptr<DatasetReader>> opened = OpenDataset(a.dataset, dataset_config.reader);
  if (!opened) return ReportError(opened.status());
  Expected<MeasurementStream> stream = MeasurementStream::Create(**opened, dataset_config.stream);
  if (!stream) return ReportError(stream.status());
  const DatasetDescription& description = stream->description();
  int lidar = -1;
  bool has_imu = false;
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    if (description.streams[s].kind == SensorKind::kLidar && lidar < 0) lidar = static_cast<int>(s);
    has_imu |= description.streams[s].kind == SensorKind::kImu;
  }
  if (lidar < 0)
    return ReportError(Status::Error(
        a.dataset + ": no LiDAR stream, which LO needs (streams: " + StreamList(description) + ")"));

  RunReport report;
  report.dataset = a.dataset;
  report.format = std::string(DatasetFormatName(description.format));
  report.mode = "lo (LiDAR-only odometry on " + description.streams[lidar].name + ")";
  report.output_frame = a.output_frame;
  if (a.mode == "auto" && has_imu) {
    const std::string note = "--mode auto: the dataset has an IMU, but LIO is not built yet; ran LO instead";
    std::cerr << "ultrafusion: warning: " << note << "\n";
    report.notes.push_back(note);
  }
  if (a.no_map) report.notes.push_back("--no-map: accepted; no map stage exists yet");
  if (a.no_splat) report.notes.push_back("--no-splat: accepted; no splatting stage exists yet");
  std::optional<SE3> T_imu_lidar;
  if (a.output_frame == "imu") {
    T_imu_lidar = ImuFromLidar(description, lidar);
    if (!T_imu_lidar)
      return ReportUsageError(Status::Error("--output-frame imu: " + a.dataset +
                                            " gives no LiDAR-to-IMU transform (T_body_sensor) for " +
                                            description.streams[lidar].name + "; use --output-frame lidar"));
  }
  Expected<estimator::LidarOdometry> odometry = estimator::LidarOdometry::Create(lo_config);
  if (!odometry) return ReportUsageError(odometry.status());

  fs::create_directories(a.out, error);
  if (error) return ReportError(Status::Error(a.out + ": cannot create the folder: " + error.message()));
  const Clock::time_point start = Clock::now();
  std::vector<double> ms_per_scan;
  std::vector<Keyframe> keyframes;
  double ms_total = 0;
  {
    ScanProgress progress;
    while (true) {
      Expected<std::optional<Measurement>> next = stream->Next();
      if (!next) return FailAndClean(a.out, ReportError(next.status()));
      if (!next->has_value()) break;
      const auto* scan = std::get_if<LidarScan>(&(*next)->data);
      if (scan == nullptr || (*next)->stream != lidar) continue;
      // Wall time of one scan: registration plus releasing the keyframes that left the window.
      const Clock::time_point scan_start = Clock::now();
      if (Status s = odometry->AddScan(*scan); !s.ok()) return FailAndClean(a.out, ReportError(s));
      for (Keyframe& k : odometry->TakeFinished()) keyframes.push_back(std::move(k));
      ms_per_scan.push_back(MillisecondsSince(scan_start));
      ms_total += ms_per_scan.back();
      progress.Update(static_cast<std::int64_t>(ms_per_scan.size()), ms_total);
    }
    odometry->Finish();
    for (Keyframe& k : odometry->TakeFinished()) keyframes.push_back(std::move(k));
  }
  Trajectory trajectory;  // T_world_lidar at each keyframe (world = the first LiDAR pose)
  for (const Keyframe& k : keyframes) {
    if (!trajectory.stamps.empty() && k.stamp <= trajectory.stamps.back())
      continue;  // keep stamps increasing
    trajectory.stamps.push_back(k.stamp);
    trajectory.poses.push_back(k.T_world_body);
  }
  if (T_imu_lidar) trajectory = ToImuFrame(trajectory, *T_imu_lidar);
  if (trajectory.empty())
    return FailAndClean(
        a.out, ReportError(Status::Error(a.dataset + ": the odometry produced no pose (" +
                                         std::to_string(ms_per_scan.size()) + " scans, " +
                                         std::to_string(odometry->warnings().size()) + " warnings)")));

  report.scans = static_cast<std::int64_t>(ms_per_scan.size());
  report.keyframes = static_cast<std::int64_t>(trajectory.size());
  report.skipped = report.scans - static_cast<std::int64_t>(keyframes.size());
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
  std::printf("  wrote %s: trajectory.tum, trajectory_kitti.txt, timing.json, config.yaml, report.md%s\n",
              a.out.c_str(), report.accuracy.plots.empty() ? "" : ", plots/");
  return kExitOk;
}

}  // namespace

Subcommand AddRunCommand(CLI::App& app) {
  auto a = std::make_shared<RunArguments>();
  CLI::App* run = app.add_subcommand("run", "Run the odometry over a dataset: trajectory, timing and report");
  run->add_option("DATASET", a->dataset, "ROS1 .bag file, or a KITTI-style, EuRoC or ultrafusion folder")
      ->required();
  run->add_option("--out", a->out, "Output folder (new or empty)")->required();
  run->add_option("--config", a->config, "YAML file with dataset: and lo: sections (see configs/kitti.yaml)")
      ->check(CLI::ExistingFile);
  run->add_option("--mode", a->mode,
                  "auto: LIO with an IMU, else LO; lo: LiDAR only; lio: LiDAR + IMU. LIO is not built yet: "
                  "--mode lio exits with a usage error, auto falls back to LO with a warning")
      ->check(CLI::IsMember({"auto", "lo", "lio"}))
      ->capture_default_str();
  run->add_option("--output-frame", a->output_frame,
                  "Frame of the written trajectory: lidar, or imu (needs the LiDAR's T_body_sensor)")
      ->check(CLI::IsMember({"lidar", "imu"}))
      ->capture_default_str();
  run->add_flag("--no-map", a->no_map, "No map output (accepted; a no-op until the map stage exists)");
  run->add_flag("--no-splat", a->no_splat, "No splatting (accepted; a no-op until the splat stage exists)");
  return {run, [a] { return RunRun(*a); }};
}

}  // namespace uf::app
