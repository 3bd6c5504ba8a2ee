#include "viewer/app/cli/calibrate_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/pipeline/calibrate/calibrate_job.h"
#include "viewer/pipeline/progress_line.h"

namespace uf::app {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

struct CalibrateArguments {
  std::string dataset, out, config;
  double max_offset_s = 0.5, window_s = 12.0;
};

int CountSolves(const pipeline::CalibrateResult& r, estimator::CalibrationWorker worker, bool accepted) {
  int n = 0;
  for (const estimator::CalibrationSolve& s : r.solves) n += s.worker == worker && s.accepted == accepted;
  return n;
}

std::string State(bool locked, bool estimated) {
  return locked ? "locked" : estimated ? "not locked, latest accepted candidate" : "no estimate";
}

void PrintResult(const pipeline::CalibrateResult& r, const estimator::OnlineCalibrationOptions& options) {
  using estimator::CalibrationWorker;
  std::printf("calibrate: %s (LiDAR) against %s (IMU): %lld scans, %lld poses, %lld IMU samples\n",
              r.lidar_stream.c_str(), r.imu_stream.c_str(), static_cast<long long>(r.scans),
              static_cast<long long>(r.poses), static_cast<long long>(r.imu_samples));
  if (r.solves.empty())
    std::printf(
        "  no solve: the odometry's poses span %.1f s, the first solve needs %.1f s (%.1f s of overlap "
        "plus twice --max-offset)\n",
        ToSeconds(r.last_pose - r.first_pose), options.time.min_overlap_s + 2 * options.time.max_shift_s,
        options.time.min_overlap_s);
  const int time_ok = CountSolves(r, CalibrationWorker::kTimeOffset, true);
  const int time_refused = CountSolves(r, CalibrationWorker::kTimeOffset, false);
  std::printf("  time offset: %s (%d solves accepted, %d refused)\n",
              State(r.time_offset_locked, r.time_offset_s.has_value()).c_str(), time_ok, time_refused);
  if (r.time_offset_s)
    std::printf("    LiDAR stamps + %.4f s = IMU time (read with %+.4f s; estimated %+.4f s on top)\n",
                r.LidarTimeOffset(), ToSeconds(r.lidar_offset_read - r.imu_offset_read), *r.time_offset_s);
  if (!r.time_offset_locked && time_refused > 0)
    std::printf("    last refusal: %s\n", r.LastRefusal(CalibrationWorker::kTimeOffset).c_str());
  const int rot_ok = CountSolves(r, CalibrationWorker::kRotation, true);
  const int rot_refused = CountSolves(r, CalibrationWorker::kRotation, false);
  std::printf("  rotation: %s (%d solves accepted, %d refused)\n",
              State(r.rotation_locked, r.R_imu_lidar.has_value()).c_str(), rot_ok, rot_refused);
  if (r.R_imu_lidar) {
    // R = Rz(yaw) Ry(pitch) Rx(roll).
    const Eigen::Matrix3d& R = r.R_imu_lidar->matrix();
    std::printf("    R_imu_lidar: roll %.3f, pitch %.3f, yaw %.3f deg",
                std::atan2(R(2, 1), R(2, 2)) / kDegree, std::asin(std::clamp(-R(2, 0), -1.0, 1.0)) / kDegree,
                std::atan2(R(1, 0), R(0, 0)) / kDegree);
    if (r.T_imu_lidar_given) {
      const SO3 correction = r.T_imu_lidar_given->so3().inverse() * *r.R_imu_lidar;
      std::printf(" (%.3f deg from the given rotation)", correction.angle() / kDegree);
    }
    std::printf("\n");
  }
  if (!r.rotation_locked && r.R_imu_lidar) {
    const double sigma = r.LatestRotationSigmaDeg();
    std::printf("    latest candidate: standard deviation %.3f deg (locks at <= %.3f with %d agreeing); %s\n",
                sigma, options.max_lock_sigma_deg, options.consensus_count,
                r.UsesEstimatedRotation() ? "written, as the given rotation is more than 3 sigma from it"
                                          : "the given rotation is written, within 3 sigma of it");
  }
  if (!r.rotation_locked && rot_refused > 0)
    std::printf("    last refusal: %s\n", r.LastRefusal(CalibrationWorker::kRotation).c_str());
  if (!r.warnings.empty())
    std::printf("  %zu warnings, the first: %s\n", r.warnings.size(), r.warnings[0].c_str());
}

int RunCalibrateCommand(const CalibrateArguments& a) {
  pipeline::CalibrateRequest request;
  request.dataset = a.dataset;
  request.options.time.max_shift_s = a.max_offset_s;
  request.options.window_s = a.window_s;
  if (a.window_s < request.options.time.min_overlap_s + 2 * a.max_offset_s)
    return ReportUsageError(Status::Error("--window " + std::to_string(a.window_s) +
                                          " s: must hold the 5 s overlap plus twice --max-offset"));
  if (!a.config.empty()) {
    Expected<ConfigFile> loaded = LoadConfigFile(a.config);
    if (!loaded) return ReportUsageError(loaded.status());
    request.dataset_config = loaded->dataset;
    request.lo_config = loaded->odometry;
  }
  pipeline::ProgressLine progress("calibrate");
  Expected<pipeline::CalibrateResult> result = pipeline::RunCalibrate(
      request, [&](std::int64_t scans) { progress.Update("odometry", scans, 0, "scans"); });
  progress.EndLine();
  if (!result) return ReportError(result.status());
  PrintResult(*result, request.options);
  if (!a.out.empty()) {
    Expected<std::vector<std::string>> written = pipeline::WriteCalibrateOutputs(a.out, *result);
    if (!written) return ReportError(written.status());
    std::string names;
    for (const std::string& name : *written) names += (names.empty() ? "" : ", ") + name;
    std::printf("  wrote %s: %s\n", a.out.c_str(), names.c_str());
  }
  return kExitOk;
}

}  // namespace

Subcommand AddCalibrateCommand(CLI::App& app) {
  auto a = std::make_shared<CalibrateArguments>();
  CLI::App* command = app.add_subcommand(
      "calibrate",
      "Estimate the LiDAR-IMU time offset and rotation of a dataset (LiDAR-only odometry + IMU)");
  command->add_option("DATASET", a->dataset, "ROS1 .bag file, or a KITTI-style, EuRoC or ultrafusion folder")
      ->required();
  command->add_option("--out", a->out,
                      "Folder for calibration_estimated.yaml, calibration_solves.csv and plots/ (created)");
  command->add_option("--config", a->config, "YAML file with dataset: and lo: sections")
      ->check(CLI::ExistingFile);
  command->add_option("--max-offset", a->max_offset_s, "Largest time offset searched, +- seconds")
      ->check(CLI::Range(0.01, 2.0))
      ->capture_default_str();
  command->add_option("--window", a->window_s, "Seconds of data per solve")
      ->check(CLI::Range(2.0, 120.0))
      ->capture_default_str();
  return {command, [a] { return RunCalibrateCommand(*a); }};
}

}  // namespace uf::app
