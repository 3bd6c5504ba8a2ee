#include "viewer/app/cli/run_command.h"

#include <cstdio>
#include <filesystem>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/app/report/run_report.h"
#include "viewer/pipeline/run/run_pipeline.h"

namespace uf::app {

using pipeline::RunRequest;
namespace {

namespace fs = std::filesystem;
using pipeline::RunRequest;

struct RunArguments {
  std::string dataset, out, config, mode = "auto", output_frame;  // output_frame "": the mode's body
  std::string from;    // "map" / "splat": re-run from that stage on the outputs of an earlier run in --out
  std::string device;  // the splat stage's Vulkan device ("": the default)
  bool no_map = false, no_splat = false, no_mesh = false, calibrate_online = false;
  double map_voxel_m = 0.05;
  double calibration_hold_s = 15.0;
  int overlay_every = 50;
};

// The options as the pipeline takes them, with the sections of --config.
Expected<RunRequest> MakeRequest(const RunArguments& a) {
  RunRequest r;
  r.dataset = a.dataset, r.out = a.out;
  Expected<std::optional<pipeline::EstimatorMode>> mode = pipeline::ParseMode(a.mode);
  if (!mode) return mode.status();
  r.mode = *mode;
  if (!a.output_frame.empty()) r.output_frame = pipeline::ParseTrajectoryFrame(a.output_frame);
  r.from = a.from == "map"     ? pipeline::RunFrom::kMap
           : a.from == "splat" ? pipeline::RunFrom::kSplat
                               : pipeline::RunFrom::kStart;
  r.no_map = a.no_map, r.no_splat = a.no_splat, r.no_mesh = a.no_mesh;
  r.map_voxel_m = a.map_voxel_m;
  r.splat_device = a.device;
  r.calibrate_online = a.calibrate_online;
  r.calibration_hold_s = a.calibration_hold_s;
  r.overlay_every = a.overlay_every;
  if (a.config.empty()) return r;
  Expected<ConfigFile> loaded = LoadConfigFile(a.config);
  if (!loaded) return loaded.status();
  r.dataset_config = loaded->dataset, r.lo_config = loaded->odometry, r.wio_config = loaded->wio;
  // config.yaml records it absolute, so that `splat RUN_DIR` and `run --from` find it from anywhere.
  std::string& calibration = r.dataset_config.reader.calibration_file;
  if (!calibration.empty()) calibration = fs::absolute(calibration).string();
  r.splat_config = loaded->splat;
  return r;
}

void PrintSummary(const fs::path& out, const pipeline::RunSummary& s) {
  const pipeline::OdometrySummary& o = s.odometry;
  // Scans fed (LiDAR window) or nodes solved (WIO).
  const long long steps = o.step == "scan" ? o.scans : static_cast<long long>(o.timing.steps);
  if (steps > 0)
    std::printf("run: %s, %lld %ss, %lld poses, %.1f ms/%s mean (%.1f p95), %lld warnings\n", s.mode.c_str(),
                steps, o.step.c_str(), static_cast<long long>(o.keyframes), o.timing.mean, o.step.c_str(),
                o.timing.p95, static_cast<long long>(o.reader_warnings.size() + o.odometry_warnings.size()));
  std::printf("%s", pipeline::FormatStageTable(s.stages).c_str());
  if (!o.initialization.empty()) std::printf("  initialized: %s\n", o.initialization.c_str());
  if (o.online_calibration && o.calibration_estimates) {
    const pipeline::CalibrateResult& c = *o.calibration_estimates;
    std::printf("  online calibration (the window waited %.1f s for the locks): ",
                o.online_calibration->held_s);
    if (o.online_calibration->offset_applied_from)
      std::printf("time offset %+.4f s locked and applied (%lld re-stamped scans left out)",
                  o.online_calibration->offset_applied_s,
                  static_cast<long long>(o.online_calibration->scans_left_out));
    else
      std::printf("no time offset locked (the given one kept)");
    if (o.online_calibration->rotation_applied_at)
      std::printf("; rotation locked and applied (%.3f deg)\n", c.RotationFromGivenDeg());
    else
      std::printf("; rotation %s (the given one kept)\n", !o.online_calibration->rotation_refused.empty()
                                                              ? "locked, not applied"
                                                          : c.R_imu_lidar ? "estimated, not locked"
                                                                          : "not estimated");
  }
  if (s.accuracy.evaluated) std::printf("  ATE (SE3-aligned RMSE): %.4f m\n", s.accuracy.ape_rmse_m);
  if (s.accuracy.yaw_ape_rmse_m)
    std::printf("  ATE (yaw-aligned RMSE, a tilt counts): %.4f m\n", *s.accuracy.yaw_ape_rmse_m);
  if (const auto& track = s.accuracy.gnss_track)
    std::printf("  against the GNSS track (%d fixes, %s): horizontal RMSE %.3f m, vertical %.3f m\n",
                track->fixes, track->aligned ? "fitted" : "georeferenced", track->horizontal_rmse_m,
                track->vertical_rmse_m);
  if (s.map) std::printf("  map: %s\n", s.map->summary.c_str());
  if (s.splat) {
    const pipeline::SplatMetrics& m = s.splat->metrics;
    std::printf(
        "  splats: %zu Gaussians, held-out PSNR %.2f dB, SSIM %.3f (%zu views), %d iterations at %.2f/s on "
        "%s\n",
        m.gaussians, m.test.psnr, m.test.ssim, m.views_test, m.iterations, m.iterations_per_s(),
        m.device.c_str());
  }
  std::printf("  wrote %s (report.md, report.html, config.yaml and the outputs above)\n", out.c_str());
}

int RunRun(const RunArguments& a) {
  Expected<RunRequest> request = MakeRequest(a);
  if (!request) return ReportUsageError(request.status());
  pipeline::PlanErrorKind kind;
  Expected<pipeline::RunPlan> plan = pipeline::PlanRun(std::move(*request), kind);
  if (!plan)
    return kind == pipeline::PlanErrorKind::kUsage ? ReportUsageError(plan.status())
                                                   : ReportError(plan.status());
  fs::path out;
  Expected<pipeline::RunSummary> summary = pipeline::RunPipeline(*plan, out);
  if (!summary) return ReportError(summary.status());
  const Status written = WriteRunReports(out, *summary);  // whether or not a stage failed
  PrintSummary(out, *summary);
  if (const pipeline::StageRecord* failed = pipeline::FailedStage(summary->stages))
    return ReportError(Status::Error("the " + failed->name + " stage failed: " + failed->message + " (see " +
                                     (out / "report.md").string() + ")"));
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
                  "YAML file with dataset:, lo:, lio:, wio: and splat: sections (see configs/kitti.yaml, "
                  "configs/run-sim.yaml, configs/husky.yaml, configs/splat.yaml)")
      ->check(CLI::ExistingFile);
  run->add_option(
         "--mode", a->mode,
         "auto: the richest the dataset supports (LIO with an IMU and the LiDAR's extrinsic, else LO; "
         "wheel (W) and GNSS (G) factors with their streams and extrinsics; without a LiDAR, the inertial "
         "window on the IMU with the wheel and/or the camera); lo, lio, lwio, lwo, lio+g, lwgio, wio, wgio, "
         "vio, vwio, vgio, vwgio, lvio, lvwio, lvio+g, lvwgio")
      ->capture_default_str();
  run->add_option("--output-frame", a->output_frame,
                  "Frame of the written trajectory: lidar or imu (needs the LiDAR's T_body_sensor); default: "
                  "lidar for LO, imu for LIO and WIO")
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
  run->add_flag(
      "--calibrate-online", a->calibrate_online,
      "LIO: estimate the LiDAR-IMU time offset and rotation while running (a LiDAR-only branch feeds "
      "the calibration workers until they lock); the window waits for them (--calibration-hold), the "
      "locked offset re-stamps the scans, the locked rotation replaces the given one (LiDAR poses kept); "
      "both are written to calibration_estimated.yaml");
  run->add_option("--calibration-hold", a->calibration_hold_s,
                  "With --calibrate-online: seconds of data (from the first measurement) the window waits, "
                  "held in memory, for the time offset and the rotation to lock before it starts; 0: it "
                  "starts at once and each applies from its lock on")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  run->add_option("--overlay-every", a->overlay_every,
                  "Modes with the camera (vio, vwio, ...): an overlay of the tracks on every N-th frame in "
                  "plots/tracks_<stamp ns>.png (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run->add_option("--device", a->device,
                  "Vulkan device of the splat and views stages: index or part of its name (default: a GPU if "
                  "any, else lavapipe on the CPU); checked before the odometry runs");
  return {run, [a] { return RunRun(*a); }};
}

}  // namespace uf::app
