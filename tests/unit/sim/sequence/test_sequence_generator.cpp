// The simulator end to end: a sequence generated into a folder and read back through the dataset reader
// agrees with the scene, the ground truth and the true calibration it was written with, and the given
// calibration carries exactly the injected errors.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/rosbag/rosbag_reader.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "odometry/sim/sequence/sim_trajectory.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/sim/sequence/sequence_test_support.h"

namespace uf::sim {
namespace {

namespace fs = std::filesystem;

constexpr double kDelay = 0.05;  // s, the LiDAR stamps run late by this

SimulationConfig SmallConfig() {
  SimulationConfig config;
  config.duration_s = 2.5;
  config.seed = 7;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 1.0;
  config.lidar.model.range_noise_std_m = 0.0;
  config.lidar.placement.T_body_sensor =
      SE3(SO3::Exp(Eigen::Vector3d(0.02, -0.01, 0.3)), Eigen::Vector3d(0.1, -0.2, 0.3));
  config.lidar.placement.stamp_delay_s = kDelay;
  config.lidar.placement.rotation_error_deg = Eigen::Vector3d(0.0, 0.0, 2.0);
  config.camera.model.pinhole = {.width = 160, .height = 120, .fx = 100, .fy = 100, .cx = 79.5, .cy = 59.5};
  return config;
}

// T_world_body at t from the ground-truth file (200 Hz): slerp/lerp between the two poses around t.
SE3 PoseAt(const Trajectory& truth, Stamp t) {
  const auto after = std::upper_bound(truth.stamps.begin(), truth.stamps.end(), t);
  const std::size_t i = std::clamp<std::size_t>(after - truth.stamps.begin(), 1, truth.size() - 1);
  const double s = double(t - truth.stamps[i - 1]) / double(truth.stamps[i] - truth.stamps[i - 1]);
  return Interpolate(truth.poses[i - 1], truth.poses[i], s);
}

TEST(SequenceGenerator, LidarPointsLieOnTheSceneWithTheTrueCalibrationAndClock) {
  testing::TempDir dir;
  const SimulationConfig config = SmallConfig();
  auto summary = GenerateSequence(config, dir.path() / "seq");
  ASSERT_TRUE(summary.ok()) << summary.error();

  auto truth = ReadTumTrajectory((dir.path() / "seq/groundtruth.tum").string());
  ASSERT_TRUE(truth.ok()) << truth.error();
  EXPECT_NEAR(double(truth->size()), 2.5 * 200 + 1, 1.0);  // >= 100 Hz body trajectory
  auto calibration_true = ReadCalibrationFile(dir.path() / "seq/calibration_true.yaml");
  auto calibration_given = ReadCalibrationFile(dir.path() / "seq/calibration.yaml");
  ASSERT_TRUE(calibration_true.ok() && calibration_given.ok());
  const SensorCalibration& lidar_true = *calibration_true->Find("lidar");
  const SensorCalibration& lidar_given = *calibration_given->Find("lidar");
  EXPECT_EQ(lidar_true.time_offset, -FromSeconds(kDelay));
  EXPECT_EQ(lidar_given.time_offset, 0);
  // The given extrinsic is off by exactly the injected 2 degrees about the lidar's z axis.
  const Eigen::Vector3d error = (lidar_true.T_body_sensor.inverse() * lidar_given.T_body_sensor).so3().Log();
  EXPECT_NEAR(error.z(), 2.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(error.head<2>().norm(), 0.0, 1e-12);

  // The scene again, from the same config (deterministic), to cast against.
  auto motion = MakeSimulationTrajectory(config);
  ASSERT_TRUE(motion.ok());
  auto scene = BuildScene({config.scene, config.seed, motion->poses, config.body_height_m, config.origin});
  ASSERT_TRUE(scene.ok());
  auto caster = RayCaster::Create(*scene);
  ASSERT_TRUE(caster.ok());

  auto reader = OpenDataset(dir.path() / "seq", DatasetOptions{});
  ASSERT_TRUE(reader.ok()) << reader.error();
  int scans = 0;
  double worst_true = 0.0, worst_delay_ignored = 0.0;
  for (const Measurement& m : ReadAll(**reader)) {
    const auto* scan = std::get_if<LidarScan>(&m.data);
    if (!scan) continue;
    ++scans;
    for (std::size_t i = 0; i < scan->points.size(); i += 37) {
      const LidarPoint& p = scan->points[i];
      const Eigen::Vector3d point(p.x, p.y, p.z);
      const Stamp stamped = scan->stamp + p.offset_ns;
      // Distance along the beam from the sensor to the first surface, against the point's range.
      auto miss = [&](Stamp t) {
        const SE3 T_world_lidar = PoseAt(*truth, t) * lidar_true.T_body_sensor;
        const Eigen::Vector3d origin = T_world_lidar.translation();
        const Eigen::Vector3d direction = (T_world_lidar * point - origin).normalized();
        const RayHit hit = caster->Cast(Ray{origin.cast<float>(), direction.cast<float>(), 1000.0f});
        return hit.hit() ? std::abs(hit.distance - point.norm()) : 1e9;
      };
      worst_true = std::max(worst_true, miss(stamped + lidar_true.time_offset));
      worst_delay_ignored = std::max(worst_delay_ignored, miss(stamped));
    }
  }
  EXPECT_EQ(scans, 25);  // whole 0.1 s sweeps in 2.5 s: starts 0.0 .. 2.4 s
  EXPECT_LT(worst_true, 5e-3) << "range noise is off: points must lie on the surfaces";
  EXPECT_GT(worst_delay_ignored, 0.05) << "ignoring the 50 ms clock offset must be visible";
}

TEST(SequenceGenerator, AStereoRigsSecondCameraSitsTheBaselineToTheRight) {
  testing::TempDir dir;
  SimulationConfig config = SmallConfig();
  config.duration_s = 2;
  config.lidar.enabled = false;
  config.camera.stereo_baseline_m = 0.4;
  config.camera.placement.rotation_error_deg = Eigen::Vector3d(1.0, -2.0, 3.0);
  config.camera.placement.translation_error_m = Eigen::Vector3d(0.01, 0.02, -0.03);
  auto summary = GenerateSequence(config, dir.path() / "seq");
  ASSERT_TRUE(summary.ok()) << summary.error();
  auto calibration_true = ReadCalibrationFile(dir.path() / "seq/calibration_true.yaml");
  auto calibration_given = ReadCalibrationFile(dir.path() / "seq/calibration.yaml");
  ASSERT_TRUE(calibration_true.ok() && calibration_given.ok());
  // cam1 is 0.4 m along cam0's x axis (its right), in the truth and in what the user is given: the rig's
  // error is cam0's, its relative extrinsic exact.
  const SE3 baseline(SO3(), Eigen::Vector3d(0.4, 0, 0));
  for (const Calibration* calibration : {&*calibration_true, &*calibration_given}) {
    const SE3 left = calibration->Find("cam0")->T_body_sensor,
              right = calibration->Find("cam1")->T_body_sensor;
    EXPECT_LT(((left * baseline).inverse() * right).Log().norm(), 1e-9);
  }
  const SE3 true_left = calibration_true->Find("cam0")->T_body_sensor;
  EXPECT_GT((true_left.inverse() * calibration_given->Find("cam0")->T_body_sensor).so3().angle(), 0.06);
  // Both cameras' frames at the same stamps, with their indices in the rig, and not the same pictures.
  auto reader = OpenDataset(dir.path() / "seq", DatasetOptions{});
  ASSERT_TRUE(reader.ok()) << reader.error();
  std::vector<Stamp> stamps[2];
  std::vector<std::vector<std::uint8_t>> bytes[2];
  for (const Measurement& m : ReadAll(**reader))
    if (const auto* frame = std::get_if<CameraFrame>(&m.data)) {
      ASSERT_TRUE(frame->camera == 0 || frame->camera == 1) << frame->camera;
      stamps[frame->camera].push_back(frame->stamp);
      bytes[frame->camera].push_back(frame->encoded.bytes);
    }
  EXPECT_EQ(stamps[0].size(), 21u);  // 0 to 2 s at 10 Hz
  EXPECT_EQ(stamps[0], stamps[1]);
  for (std::size_t k = 0; k < bytes[0].size() && k < bytes[1].size(); ++k)
    EXPECT_NE(bytes[0][k], bytes[1][k]);
}

TEST(SequenceGenerator, SameSeedSameBytesAndTheBagMatchesTheFolder) {
  testing::TempDir dir;
  SimulationConfig config = SmallConfig();
  config.duration_s = 2.0;
  config.write_bag = true;
  config.threads = 1;
  auto first = GenerateSequence(config, dir.path() / "a");
  ASSERT_TRUE(first.ok()) << first.error();
  config.threads = 2;
  auto second = GenerateSequence(config, dir.path() / "b");
  ASSERT_TRUE(second.ok());
  for (const char* file : {"lidar.bin", "imu.csv", "wheel.csv", "gnss.csv", "groundtruth.tum", "sim.bag"})
    EXPECT_EQ(testing::ReadText((dir.path() / "a" / file).string()),
              testing::ReadText((dir.path() / "b" / file).string()))
        << file;

  auto folder = OpenDataset(dir.path() / "a", DatasetOptions{});
  auto bag = OpenRosBag(dir.path() / "a/sim.bag", DatasetOptions{});
  ASSERT_TRUE(folder.ok() && bag.ok());
  const std::vector<Measurement> from_folder = ReadAll(**folder);
  const std::vector<Measurement> from_bag = ReadAll(**bag);
  ASSERT_EQ(from_folder.size(), from_bag.size());
  std::map<SensorKind, int> folder_counts, bag_counts;
  for (const Measurement& m : from_folder) ++folder_counts[KindOf(m.data)];
  for (const Measurement& m : from_bag) ++bag_counts[KindOf(m.data)];
  EXPECT_EQ(folder_counts, bag_counts);
  EXPECT_EQ(bag_counts.size(), 5u);
  EXPECT_EQ(second->streams.size(), 5u);
}

TEST(SequenceGenerator, BadInputLeavesNothingBehind) {
  testing::TempDir dir;
  SimulationConfig config = SmallConfig();
  config.trajectory.file =
      dir.Write("short.tum", "1.0 0 0 0 0 0 0 1\n1.1 1 0 0 0 0 0 1\n1.2 2 0 0 0 0 0 1\n");
  auto result = GenerateSequence(config, dir.path() / "out");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("short.tum: 3 poses"), std::string::npos) << result.error();
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out/dataset.yaml"));

  config = SmallConfig();
  config.lidar.model.rate_hz = -5;
  result = GenerateSequence(config, dir.path() / "out2");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("sim.lidar.rate_hz"), std::string::npos) << result.error();
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out2"));

  fs::create_directories(dir.path() / "full");
  dir.Write("full/keep.txt", "x");
  result = GenerateSequence(SmallConfig(), dir.path() / "full");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("not empty"), std::string::npos) << result.error();
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path() / "full"), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace uf::sim
