// Visual-inertial odometry test support: a short simulated drive with the IMU and the camera (or a stereo
// rig), and a VIO run over it with what the tests check (the estimate against the truth, the window's
// statistics, warnings).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "odometry/estimator/inertial_odometry/inertial_odometry.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/window_truth_support.h"

namespace uf::estimator::testing {

// The urban drive (1 s at rest, then off, ~7.5 m/s cruising) or `trajectory` (TUM) with the IMU and the
// forward camera only (and its stereo partner, with camera.stereo_baseline_m).
inline std::filesystem::path Simulate(const uf::testing::TempDir& dir, double duration_s,
                                      const std::string& trajectory = "",
                                      const std::function<void(sim::SimulationConfig&)>& adjust = nullptr) {
  sim::SimulationConfig config;
  config.duration_s = duration_s;
  config.trajectory.file = trajectory;
  config.lidar.enabled = config.wheel.enabled = config.gnss.enabled = false;
  if (adjust) adjust(config);
  const std::filesystem::path out = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, out);
  EXPECT_TRUE(summary.ok()) << summary.error();
  return out;
}

struct VioRun {
  Trajectory estimate;
  std::vector<std::string> warnings;
  std::string initialization;
  SensorFactorStats factors;
  int frames = 0;
  double first_speed_mps = 0;  // of the first keyframe
  Eigen::Vector3d first_gyro_bias = Eigen::Vector3d::Zero();  // likewise
  double reprojection_px = 0;  // the largest mean reprojection error after a node's solve
  int min_landmarks = std::numeric_limits<int>::max();  // the fewest in the window once moving
  double ate_m = std::numeric_limits<double>::infinity();
  KittiDrift drift;
  std::vector<CameraCheck> camera_checks;  // the reliability scheduling's, every frame checked
};

// against_truth: the ATE and drift against the folder's ground truth (a straight line admits no alignment).
inline VioRun RunVio(const std::filesystem::path& folder,
                     const std::function<void(InertialOdometryConfig&)>& adjust = nullptr,
                     bool against_truth = true) {
  VioRun run;
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  InertialOdometryConfig config;
  config.visual.max_solver_time_s = 10;  // only the iteration budget: the results do not depend on the load
  config.use_wheel = false;
  config.use_camera = true;
  for (const StreamInfo& stream : (*reader)->description().streams) {
    if (stream.kind != SensorKind::kCamera || !stream.T_body_sensor) continue;
    if (!config.camera) {
      config.camera = stream.camera_model;
      config.T_body_camera = *stream.T_body_sensor;
    } else if (!config.right_camera) {  // a stereo rig's second camera (cam1)
      config.right_camera = stream.camera_model;
      config.T_body_right_camera = *stream.T_body_sensor;
    }
  }
  if (adjust) adjust(config);
  auto vio = InertialOdometry::Create(config);
  EXPECT_TRUE(vio.ok()) << vio.error();
  if (!vio) return run;
  const Status read = ForEachMeasurement(**reader, [&](Measurement& m) {
    if (auto* sample = std::get_if<ImuSample>(&m.data)) return vio->AddImu(*sample);
    if (auto* frame = std::get_if<CameraFrame>(&m.data)) {
      if (Status s = DecodeCameraFrame(*frame); !s.ok()) return s;
      return frame->camera == 1 ? vio->AddRightCameraFrame(*frame) : vio->AddCameraFrame(*frame);
    }
    return Status();
  });
  EXPECT_TRUE(read.ok()) << read.message();
  vio->Finish();
  const std::vector<InertialOdometryStats> nodes = vio->TakeProcessedStats();
  for (const InertialOdometryStats& node : nodes) {
    run.reprojection_px = std::max(run.reprojection_px, node.reprojection_px);
    if (node.stamp - nodes.front().stamp > 2 * kNanosecondsPerSecond)  // moving: parallax
      run.min_landmarks = std::min(run.min_landmarks, node.landmarks);
  }
  for (const Keyframe& k : vio->TakeFinished()) {
    EXPECT_TRUE(k.T_world_body.matrix().allFinite()) << ToSeconds(k.stamp);
    if (run.estimate.empty()) {
      run.first_speed_mps = k.velocity.norm();
      run.first_gyro_bias = k.bias_gyro;
    }
    run.estimate.stamps.push_back(k.stamp);
    run.estimate.poses.push_back(k.T_world_body);
    run.camera_checks.insert(run.camera_checks.end(), k.camera_checks.begin(), k.camera_checks.end());
  }
  run.frames = static_cast<int>(vio->TakeTrackedFrames().size());
  run.warnings = vio->warnings();
  run.initialization = vio->initialization();
  run.factors = vio->sensor_factors();
  if (run.estimate.empty() || !against_truth) return run;  // never initialized, or no truth wanted
  const testing::TruthFigures figures = testing::AgainstTruth(folder, run.estimate);
  run.ate_m = figures.ate_m;
  run.drift = figures.drift;
  return run;
}

}  // namespace uf::estimator::testing
