// bench_lio_init: the LIO initialization (docs/METHOD.md "Observability-aware initialization") on simulated
// starts: for each scene and seed, a sequence from the simulator (32-beam LiDAR, IMU; the default trajectory:
// 1 s at rest, then driving off), fed to LIO from its first sample (a static start) and from --moving-from
// seconds in (a moving start: the measurements before are dropped). Per run: the chosen mode, the latency
// from the first IMU sample fed to the admitted state (stream time), the attempts, the admitted state's
// gravity direction error and velocity error against the simulator's ground truth (both in the imu frame, so
// free of the world's yaw), the predicted gravity sigma, and the ATE (SE3-aligned) of the whole run after.
// Nothing is asserted. The solver's wall-time budget is lifted, so the figures do not depend on the load.
//   usage: bench_lio_init [--scenes urban,wild,warehouse] [--seeds 1,2,3] [--starts static,moving]
//                         [--duration S] [--moving-from S] [--work DIR]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/sequence/sequence_generator.h"

namespace {

using namespace uf;

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

struct Row {
  std::string mode = "-";
  double latency_s = NAN, gravity_deg = NAN, velocity_mps = NAN, sigma_deg = NAN, ate_m = NAN;
  int attempts = 0, deferred = 0, rejected = 0, warnings = 0;
  std::string ate_note;  // why there is no ATE
};

// The true velocity (world) at t from the ground truth's poses 5 ms either side.
Eigen::Vector3d TrueVelocity(const Trajectory& truth, Stamp t) {
  const Stamp h = 5'000'000;
  const auto a = truth.PoseAt(t - h), b = truth.PoseAt(t + h);
  if (!a || !b) return Eigen::Vector3d::Constant(NAN);
  return (b->translation() - a->translation()) / ToSeconds(2 * h);
}

Row RunLio(const std::filesystem::path& folder, double from_s, const Trajectory& truth) {
  Row row;
  auto reader = OpenDataset(folder.string());
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.error().c_str());
    return row;
  }
  estimator::LidarOdometryConfig config;  // configs/run-sim.yaml: the defaults but the finer scan voxel
  config.use_imu = true;
  config.input_voxel_m = 0.5;
  config.max_solver_time_s = 10;
  config.T_body_lidar = FindSensors((*reader)->description()).T_imu_lidar.value_or(SE3());
  auto lio = estimator::LidarOdometry::Create(config);
  if (!lio.ok()) {
    std::fprintf(stderr, "%s\n", lio.error().c_str());
    return row;
  }
  const Stamp from = truth.stamps.front() + FromSeconds(from_s);
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && scan->stamp >= from)
      return lio->AddScan(*scan);
    if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && sample->stamp >= from)
      return lio->AddImu(*sample);
    return Status();
  });
  if (!read.ok()) std::fprintf(stderr, "read: %s\n", read.message().c_str());
  const estimator::InitializationRecord record = lio->initialization_record();
  lio->Finish();
  Trajectory estimate;
  for (const Keyframe& k : lio->TakeFinished()) {
    estimate.stamps.push_back(k.stamp);
    estimate.poses.push_back(k.T_world_body);
  }
  row.warnings = static_cast<int>(lio->warnings().size());
  row.attempts = record.attempts;
  row.deferred = record.deferred;
  row.rejected = record.rejected;
  if (auto result = Evaluate(truth, estimate, EvalOptions{}); result.ok())
    row.ate_m = result->ape.rmse;
  else
    row.ate_note = result.error();
  if (!record.admitted) return row;
  row.mode = std::string(1, estimator::InitModeLetter(record.mode));
  row.latency_s = record.latency_s;
  row.sigma_deg = record.tilt_sigma_deg;
  const auto T_true = truth.PoseAt(record.admitted_at);
  if (!T_true) return row;
  const SO3 R_true = T_true->so3();
  const Eigen::Vector3d up(0, 0, 1);
  const Eigen::Vector3d up_true = R_true.inverse() * up, up_estimated = record.R_world_imu.inverse() * up;
  row.gravity_deg = std::acos(std::clamp(up_true.dot(up_estimated), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  row.velocity_mps = (R_true.inverse() * TrueVelocity(truth, record.admitted_at) -
                      record.R_world_imu.inverse() * record.velocity)
                         .norm();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"urban", "wild", "warehouse"};
  std::vector<std::string> seeds = {"1", "2", "3"};
  std::vector<std::string> starts = {"static", "moving"};
  double duration = 12, moving_from = 3;
  std::string work;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--scenes")
      scenes = Split(value);
    else if (flag == "--seeds")
      seeds = Split(value);
    else if (flag == "--starts")
      starts = Split(value);
    else if (flag == "--duration")
      duration = std::stod(value);
    else if (flag == "--moving-from")
      moving_from = std::stod(value);
    else if (flag == "--work")
      work = value;
    else {
      std::fprintf(stderr, "unknown option %s\n", flag.c_str());
      return 2;
    }
  }
  const std::filesystem::path root =
      work.empty() ? std::filesystem::temp_directory_path() / "bench_lio_init" : std::filesystem::path(work);
  std::printf("bench_lio_init: %.0f s sequences, moving starts from %.1f s; load average before %s\n",
              duration, moving_from, bench::LoadAverage().c_str());
  std::printf("%-10s %-7s %4s %4s %9s %9s %9s %9s %9s %8s %s\n", "scene", "start", "seed", "mode",
              "latency_s", "grav_deg", "vel_mps", "sigma_deg", "ATE_m", "warn",
              "attempts (deferred/rejected)");
  double latency_sum = 0, gravity_max = 0, velocity_max = 0;
  int admitted = 0, runs = 0;
  for (const std::string& scene : scenes) {
    for (const std::string& seed : seeds) {
      sim::SimulationConfig config;
      config.scene = scene;
      config.seed = std::stoull(seed);
      config.duration_s = duration;
      config.camera.enabled = config.wheel.enabled = config.gnss.enabled = false;
      const std::filesystem::path folder = root / (scene + "-" + seed);
      if (!std::filesystem::exists(folder / "dataset.yaml")) {
        std::filesystem::remove_all(folder);
        if (auto made = sim::GenerateSequence(config, folder); !made.ok()) {
          std::fprintf(stderr, "sim %s: %s\n", scene.c_str(), made.error().c_str());
          continue;
        }
      }
      auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
      if (!truth.ok()) {
        std::fprintf(stderr, "%s\n", truth.error().c_str());
        continue;
      }
      for (const std::string& start : starts) {
        const double from = start == "moving" ? moving_from : 0.0;
        const Row row = RunLio(folder, from, *truth);
        ++runs;
        if (std::isfinite(row.latency_s)) {
          ++admitted;
          latency_sum += row.latency_s;
          gravity_max = std::max(gravity_max, row.gravity_deg);
          velocity_max = std::max(velocity_max, row.velocity_mps);
        }
        std::printf("%-10s %-7s %4s %4s %9.3f %9.3f %9.4f %9.3f %9.4f %8d %d (%d/%d)\n", scene.c_str(),
                    start.c_str(), seed.c_str(), row.mode.c_str(), row.latency_s, row.gravity_deg,
                    row.velocity_mps, row.sigma_deg, row.ate_m, row.warnings, row.attempts, row.deferred,
                    row.rejected);
        if (!row.ate_note.empty()) std::printf("  (no ATE: %s)\n", row.ate_note.c_str());
        std::fflush(stdout);
      }
    }
  }
  std::printf(
      "admitted %d of %d; mean latency %.3f s; largest gravity error %.3f deg, velocity error %.4f m/s\n",
      admitted, runs, admitted ? latency_sum / admitted : NAN, gravity_max, velocity_max);
  std::printf("load average after %s\n", bench::LoadAverage().c_str());
  return 0;
}
