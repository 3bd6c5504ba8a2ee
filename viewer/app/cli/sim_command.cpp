#include "viewer/app/cli/sim_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <random>

#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/config/config_file.h"
#include "viewer/pipeline/progress_line.h"

namespace uf::app {

using pipeline::ProgressLine;
namespace {
namespace fs = std::filesystem;

// Options given on the command line; unset ones leave the config's value.
struct SimArguments {
  std::string out, config, trajectory, trajectory_format, lidar;
  std::optional<std::string> scene;
  std::optional<double> duration_s, body_height_m, lidar_rate_hz;
  std::optional<std::string> motion;
  std::optional<std::uint64_t> seed;
  std::optional<int> threads;
  bool bag = false, no_camera = false, no_wheel = false, no_gnss = false, print_config = false;
  std::optional<double> lidar_delay_s, lidar_rotation_error_deg, lidar_translation_error_m;
  std::optional<double> camera_delay_s, camera_rotation_error_deg, stereo_baseline_m;
};

// A vector of the given length along a direction drawn from the seed, so that "an error of 3 degrees"
// is reproducible and not always about the same axis.
Eigen::Vector3d SeededDirection(double length, std::uint64_t seed, std::uint64_t salt) {
  std::mt19937_64 random(seed * 0x9E3779B97F4A7C15ull + salt);
  std::normal_distribution<double> normal;
  Eigen::Vector3d direction(normal(random), normal(random), normal(random));
  return length * direction.normalized();
}

Status ApplyArguments(const SimArguments& a, sim::SimulationConfig& config) {
  if (a.scene) config.scene = *a.scene;
  if (a.motion) {
    Expected<sim::Motion> motion = sim::ParseMotion(*a.motion);
    if (!motion) return Status::Error("--motion: " + motion.error());
    config.trajectory.motion = *motion;
    if (*motion == sim::Motion::kHandheld) config.body_height_m = sim::kHandheldBodyHeightM;
  }
  if (a.body_height_m) config.body_height_m = *a.body_height_m;
  if (a.lidar_rate_hz) config.lidar.keyframe_rate_hz = *a.lidar_rate_hz;
  if (a.duration_s) config.duration_s = *a.duration_s;
  if (a.seed) config.seed = *a.seed;
  if (a.threads) config.threads = *a.threads;
  if (!a.trajectory.empty()) config.trajectory.file = a.trajectory;
  if (!a.trajectory_format.empty()) config.trajectory.format = a.trajectory_format;
  if (a.bag) config.write_bag = true;
  if (a.lidar == "none") config.lidar.enabled = false;
  if (!a.lidar.empty() && a.lidar != "none") config.lidar.model.model = a.lidar;
  if (a.no_camera) config.camera.enabled = false;
  if (a.no_wheel) config.wheel.enabled = false;
  if (a.no_gnss) config.gnss.enabled = false;
  if (a.lidar_delay_s) config.lidar.placement.stamp_delay_s = *a.lidar_delay_s;
  if (a.camera_delay_s) config.camera.placement.stamp_delay_s = *a.camera_delay_s;
  if (a.stereo_baseline_m) config.camera.stereo_baseline_m = *a.stereo_baseline_m;
  if (a.lidar_rotation_error_deg)
    config.lidar.placement.rotation_error_deg = SeededDirection(*a.lidar_rotation_error_deg, config.seed, 1);
  if (a.lidar_translation_error_m)
    config.lidar.placement.translation_error_m =
        SeededDirection(*a.lidar_translation_error_m, config.seed, 2);
  if (a.camera_rotation_error_deg)
    config.camera.placement.rotation_error_deg =
        SeededDirection(*a.camera_rotation_error_deg, config.seed, 3);
  return {};
}

void PrintSummary(const sim::SimulationSummary& summary, const fs::path& out) {
  std::printf("sim: %s, %.1f s, %.0f m of path, %zu scene triangles\n", summary.scene.c_str(),
              summary.duration_s, summary.path_length_m, summary.scene_triangles);
  std::printf("  %-8s %10s %10s\n", "stream", "count", "rate_hz");
  for (const auto& stream : summary.streams)
    std::printf("  %-8s %10lld %10.2f\n", stream.name.c_str(), static_cast<long long>(stream.count),
                stream.rate_hz);
  if (summary.lidar_points > 0)
    std::printf("  lidar points: %lld\n", static_cast<long long>(summary.lidar_points));
  constexpr double kDeg = 180.0 / M_PI;
  std::printf("  motion: peak body rate %.1f deg/s", summary.peak_body_rate_rad_s * kDeg);
  if (summary.max_scan_translation_m > 0.0)
    std::printf("; between consecutive scans up to %.1f deg and %.2f m", summary.max_scan_rotation_rad * kDeg,
                summary.max_scan_translation_m);
  std::printf("\n  spline fit to the poses: max %.2g mm, %.2g deg\n", summary.fit_position_error_m * 1e3,
              summary.fit_rotation_error_rad * kDeg);
  std::printf("  wall time: %.1f s scene + %.1f s sensors\n", summary.seconds_scene, summary.seconds_sensors);
  std::printf("  wrote %s: dataset.yaml, groundtruth.tum", out.string().c_str());
  for (const std::string& file : summary.files) std::printf(", %s", file.c_str());
  std::printf("\n");
}

int RunSim(const SimArguments& arguments) {
  sim::SimulationConfig config;
  if (!arguments.config.empty()) {
    Expected<ConfigFile> loaded = LoadConfigFile(arguments.config);
    if (!loaded) return ReportUsageError(loaded.status());
    config = loaded->sim;
  }
  if (Status s = ApplyArguments(arguments, config); !s.ok()) return ReportUsageError(s);
  if (Status s = sim::ValidateSimulationConfig(config); !s.ok()) return ReportUsageError(s);
  const std::string resolved = EmitSimConfig(config);
  if (arguments.print_config) {
    std::cout << resolved;
    return kExitOk;
  }
  if (arguments.out.empty()) return ReportUsageError(Status::Error("--out DIR is required"));
  std::error_code error;
  if (fs::exists(arguments.out, error) &&
      !(fs::is_directory(arguments.out, error) && fs::is_empty(arguments.out, error)))
    return ReportUsageError(
        Status::Error(arguments.out + ": exists and is not an empty folder; sim writes a new one"));

  ProgressLine progress("sim");
  auto summary = sim::GenerateSequence(
      config, arguments.out, {{"sim_config.yaml", resolved}},
      [&progress](const sim::SimulationProgress& p) { progress.Update(p.stage, p.done, p.total); });
  if (!summary) {
    // Leave no empty folder behind either.
    if (fs::is_directory(arguments.out, error) && fs::is_empty(arguments.out, error))
      fs::remove(arguments.out, error);
    return ReportError(summary.status());
  }
  PrintSummary(*summary, arguments.out);
  return kExitOk;
}

}  // namespace

Subcommand AddSimCommand(CLI::App& app) {
  auto a = std::make_shared<SimArguments>();
  CLI::App* sim = app.add_subcommand("sim", "Simulate a multi-sensor sequence with exact ground truth");
  std::string scenes;
  for (std::string_view name : sim::SceneNames()) scenes += (scenes.empty() ? "" : ", ") + std::string(name);
  sim->add_option("--scene", a->scene, "Scene: " + scenes + " (default urban)");
  sim->add_option("--out", a->out, "Output folder (new or empty)");
  sim->add_option("--duration", a->duration_s, "Seconds to simulate (default 60)");
  sim->add_option(
         "--motion", a->motion,
         "How the body moves along the scene's path: vehicle (default) or handheld (a person walking "
         "with the device, bouncing and looking around; also sets --body-height 1.4)")
      ->check(CLI::IsMember({"vehicle", "handheld"}));
  sim->add_option("--body-height", a->body_height_m,
                  "Metres of the body (IMU) above the ground (default 1.8)");
  sim->add_option("--seed", a->seed, "Random seed: the same seed gives the same sequence (default 1)");
  sim->add_option("--trajectory", a->trajectory,
                  "Follow this TUM/EuRoC/KITTI trajectory instead of the default")
      ->check(CLI::ExistingFile);
  sim->add_option("--trajectory-format", a->trajectory_format, "Format of --trajectory")
      ->check(CLI::IsMember({"auto", "tum", "kitti", "euroc"}));
  sim->add_option("--config", a->config, "YAML file with a sim: section (see configs/sim.yaml)")
      ->check(CLI::ExistingFile);
  sim->add_flag("--bag", a->bag, "Also write the measurements as a ROS1 bag (sim.bag)");
  sim->add_option("--lidar", a->lidar,
                  "LiDAR model: spinning16, spinning32, spinning64, spinning128, livox_avia, or none");
  sim->add_option("--lidar-rate", a->lidar_rate_hz,
                  "LiDAR scans written per second (keyframes, e.g. 2): sweeps keep their duration, one in "
                  "rate / this is written (default 0: every sweep)");
  sim->add_flag("--no-camera", a->no_camera, "No camera");
  sim->add_flag("--no-wheel", a->no_wheel, "No wheel odometry");
  sim->add_flag("--no-gnss", a->no_gnss, "No GNSS");
  sim->add_option("--lidar-stamp-delay", a->lidar_delay_s, "LiDAR stamps run this many seconds late");
  sim->add_option("--lidar-rotation-error", a->lidar_rotation_error_deg,
                  "Degrees of error in the given LiDAR extrinsic rotation (axis drawn from the seed)");
  sim->add_option("--lidar-translation-error", a->lidar_translation_error_m,
                  "Metres of error in the given LiDAR extrinsic translation (direction drawn from the seed)");
  sim->add_option("--camera-stamp-delay", a->camera_delay_s, "Camera stamps run this many seconds late");
  sim->add_option("--camera-rotation-error", a->camera_rotation_error_deg,
                  "Degrees of error in the given camera extrinsic rotation (axis drawn from the seed)");
  sim->add_option(
      "--stereo-baseline", a->stereo_baseline_m,
      "A stereo rig: a second camera (cam1) this many metres to the right of cam0 (default 0: none)");
  sim->add_option("--threads", a->threads,
                  "Ray-casting threads (default: all cores); output does not change");
  sim->add_flag("--print-config", a->print_config, "Print the resolved configuration and exit");
  return {sim, [a] { return RunSim(*a); }};
}

}  // namespace uf::app
