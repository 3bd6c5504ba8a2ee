// LIO on short simulated sequences end to end, shared by the LIO and LWIO tests: the sequence (LiDAR, IMU
// and optionally wheel odometry), one run of the window over it, and its ATE against the ground truth.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/lio_test_support.h"

namespace uf::estimator::testing {

// The rig of these sequences: `scene` for `duration_s` with a 16-beam LiDAR (0.4 deg) and the IMU; no
// camera, GNSS or wheel.
inline sim::SimulationConfig SimulatedRig(const std::string& scene, double duration_s) {
  sim::SimulationConfig config;
  config.scene = scene;
  config.duration_s = duration_s;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 0.4;
  config.camera.enabled = config.gnss.enabled = config.wheel.enabled = false;
  return config;
}

// The sequence of `config` in dir/sequence.
inline std::filesystem::path Generate(const uf::testing::TempDir& dir, const sim::SimulationConfig& config) {
  const std::filesystem::path out = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, out);
  EXPECT_TRUE(summary.ok()) << summary.error();
  return out;
}

// A short sequence of `scene` with LiDAR (16 beams, 0.4 deg) and IMU, and with `wheel` the wheel odometry
// (its radius off by `wheel_radius_error`, relative); `trajectory` (TUM) or the scene's default motion (1 s
// at rest, then driving off); the accelerometer clipped at `accel_saturation` (0: not).
inline std::filesystem::path Simulate(const uf::testing::TempDir& dir, double duration_s,
                                      const std::string& trajectory = "", bool wheel = false,
                                      const std::string& scene = "urban", double wheel_radius_error = 0,
                                      double accel_saturation = 0) {
  sim::SimulationConfig config = SimulatedRig(scene, duration_s);
  config.imu.noise.accel_saturation = accel_saturation;
  config.wheel.model.radius_error = wheel_radius_error;
  config.wheel.enabled = wheel;
  config.trajectory.file = trajectory;
  return Generate(dir, config);
}

// `duration_s` of the device carried by hand through `scene` (the same LiDAR and IMU).
inline std::filesystem::path SimulateHandheld(const uf::testing::TempDir& dir, double duration_s,
                                              const std::string& scene) {
  sim::SimulationConfig config = SimulatedRig(scene, duration_s);
  config.trajectory.motion = sim::Motion::kHandheld;
  config.trajectory.knot_spacing_s = sim::kHandheldKnotSpacingS;
  config.body_height_m = sim::kHandheldBodyHeightM;
  return Generate(dir, config);
}

// SE3-aligned ATE of the poses from `from` on against the simulator's ground truth.
inline double AteFrom(const std::filesystem::path& folder, const Trajectory& estimate, Stamp from) {
  Trajectory late;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    if (estimate.stamps[i] < from) continue;
    late.stamps.push_back(estimate.stamps[i]);
    late.poses.push_back(estimate.poses[i]);
  }
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  auto result = Evaluate(*truth, late, EvalOptions{});
  EXPECT_TRUE(result.ok()) << result.error();
  return result.ok() ? result->ape.rmse : std::numeric_limits<double>::infinity();
}

struct LioRun {
  Trajectory estimate;
  std::vector<Eigen::Vector3d> velocities;  // of each keyframe of estimate, world, m/s
  std::vector<std::string> warnings;
  std::string initialization;
  InitializationRecord init;
  SensorFactorStats factors;
  double ate_m = std::numeric_limits<double>::infinity();
};

// Runs LIO over the folder; `edit_imu` may change or drop (return false) each IMU sample first. With
// `edit_wheel`, LWIO: the wheel stream goes in too (each sample through it first), with the wheel's
// T_body_sensor from the dataset (the body is the IMU).
inline LioRun RunLio(
    const std::filesystem::path& folder,
    const std::function<bool(ImuSample&)>& edit_imu = [](ImuSample&) { return true; },
    const std::function<bool(WheelSample&)>& edit_wheel = nullptr, bool evaluate = true,
    const std::function<void(LidarOdometryConfig&)>& edit_config = nullptr) {
  LioRun run;
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  LidarOdometryConfig config = SimulatedLioConfig(kSimImuFromLidar);
  if (edit_config) edit_config(config);
  if (edit_wheel) {
    config.use_wheel = true;
    for (const StreamInfo& stream : (*reader)->description().streams)
      if (stream.kind == SensorKind::kWheel && stream.T_body_sensor)
        config.T_body_wheel = *stream.T_body_sensor;
  }
  auto lio = LidarOdometry::Create(config);
  EXPECT_TRUE(lio.ok()) << lio.error();
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) return lio->AddScan(*scan);
    if (auto* sample = std::get_if<ImuSample>(&m.data); sample && edit_imu(*sample))
      return lio->AddImu(*sample);
    if (auto* wheel = std::get_if<WheelSample>(&m.data); wheel && edit_wheel && edit_wheel(*wheel))
      return lio->AddWheel(*wheel);
    return Status();
  });
  EXPECT_TRUE(read.ok()) << read.message();
  lio->Finish();
  for (const Keyframe& k : lio->TakeFinished()) {
    EXPECT_TRUE(k.T_world_body.matrix().allFinite() && k.velocity.allFinite()) << ToSeconds(k.stamp);
    run.estimate.stamps.push_back(k.stamp);
    run.estimate.poses.push_back(k.T_world_body);
    run.velocities.push_back(k.velocity);
  }
  run.warnings = lio->warnings();
  run.initialization = lio->initialization();
  run.init = lio->initialization_record();
  run.factors = lio->sensor_factors();
  if (!evaluate) return run;  // e.g. a path too straight for the SE3 alignment
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  auto result = Evaluate(*truth, run.estimate, EvalOptions{});
  EXPECT_TRUE(result.ok()) << result.error();
  if (result.ok()) run.ate_m = result->ape.rmse;
  return run;
}

// The warnings one per line, for failure messages.
inline std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

}  // namespace uf::estimator::testing
