// The handheld motion and the LiDAR keyframe rate through the whole generator: which sweeps are written
// (folder and bag), that they are the very sweeps a run without the keyframe rate writes, that the others
// are never produced, the summary's motion figures against the written truth, the handheld sensors
// against groundtruth.tum, and the errors of both settings.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/rosbag/rosbag_reader.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/imu_model.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "odometry/sim/sequence/sequence_measurements.h"
#include "odometry/sim/sequence/sim_trajectory.h"
#include "tests/support/temp_dir.h"
#include "tests/support/triangle_distance.h"
#include "tests/unit/sim/sequence/sequence_test_support.h"

namespace uf::sim {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr Stamp kMs = 1'000'000;

SimulationConfig SmallConfig() {
  SimulationConfig config;
  config.scene = "warehouse";
  config.duration_s = 2.5;
  config.seed = 11;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 1.0;
  config.lidar.model.range_noise_std_m = 0.0;
  config.camera.enabled = false;
  return config;
}

std::vector<LidarScan> Scans(const std::vector<Measurement>& measurements) {
  std::vector<LidarScan> scans;
  for (const Measurement& m : measurements)
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) scans.push_back(*scan);
  return scans;
}

std::vector<Stamp> Seconds(std::initializer_list<double> seconds) {
  std::vector<Stamp> stamps;
  for (double s : seconds) stamps.push_back(std::llround(s * 1e9));
  return stamps;
}

TEST(WrittenSweepStarts, OneSweepPerKeyframePeriod) {
  const Stamp period = 100 * kMs, end = 2500 * kMs;
  EXPECT_EQ(WrittenSweepStarts(0, end, period, 10.0, 2.0), Seconds({0, 0.5, 1.0, 1.5, 2.0}));
  // Every whole sweep inside the span without a keyframe rate, or with the sweep rate itself.
  const std::vector<Stamp> all = WrittenSweepStarts(0, end, period, 10.0, 0.0);
  ASSERT_EQ(all.size(), 25u);
  EXPECT_EQ(all.back(), 2400 * kMs);
  EXPECT_EQ(WrittenSweepStarts(0, end, period, 10.0, 10.0), all);
  // No whole ratio: the sweep nearest each keyframe time, so the spacing alternates.
  EXPECT_EQ(WrittenSweepStarts(0, end, period, 10.0, 3.0), Seconds({0, 0.3, 0.7, 1.0, 1.3, 1.7, 2.0, 2.3}));
  EXPECT_EQ(WrittenSweepStarts(7, 7 + 950 * kMs, period, 10.0, 1.0), std::vector<Stamp>{7});
}

TEST(SequenceGenerator, KeyframeRateWritesEveryFifthSweepInTheFolderAndTheBag) {
  testing::TempDir dir;
  SimulationConfig config = SmallConfig();
  auto every = GenerateSequence(config, dir.path() / "every");
  ASSERT_TRUE(every.ok()) << every.error();

  config.lidar.keyframe_rate_hz = 2.0;
  config.write_bag = true;
  std::int64_t produced = 0;  // sweeps the generator produced (the progress' total of heavy items)
  auto kept = GenerateSequence(config, dir.path() / "kept", {}, [&](const SimulationProgress& p) {
    if (p.stage == std::string("sensors")) produced = p.total;
  });
  ASSERT_TRUE(kept.ok()) << kept.error();
  EXPECT_EQ(produced, 5) << "dropped sweeps must not be cast";
  ASSERT_EQ(kept->streams[1].name, "lidar");
  EXPECT_EQ(kept->streams[1].count, 5);
  EXPECT_EQ(kept->streams[1].rate_hz, 2.0);
  EXPECT_EQ(every->streams[1].count, 25);

  auto reader_every = OpenDataset(dir.path() / "every", DatasetOptions{});
  auto reader_kept = OpenDataset(dir.path() / "kept", DatasetOptions{});
  auto bag = OpenRosBag(dir.path() / "kept/sim.bag", DatasetOptions{});
  ASSERT_TRUE(reader_every.ok() && reader_kept.ok() && bag.ok());
  EXPECT_EQ((*reader_kept)->description().streams[1].nominal_rate_hz, 2.0);
  const std::vector<LidarScan> all = Scans(ReadAll(**reader_every));
  const std::vector<LidarScan> scans = Scans(ReadAll(**reader_kept));
  const std::vector<LidarScan> from_bag = Scans(ReadAll(**bag));
  ASSERT_EQ(all.size(), 25u);
  ASSERT_EQ(scans.size(), 5u);
  ASSERT_EQ(from_bag.size(), 5u);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    // 0.5 s apart, each a whole 0.1 s sweep with its point times: sweep 5k of the run that keeps them all.
    EXPECT_EQ(scans[k].stamp, config.start_stamp + static_cast<Stamp>(k) * 500 * kMs);
    EXPECT_EQ(scans[k].end - scans[k].stamp, 100 * kMs);
    EXPECT_TRUE(scans[k].has_point_times);
    EXPECT_GT(scans[k].points.back().offset_ns, 99 * kMs);
    const LidarScan& same = all[5 * k];
    EXPECT_EQ(same.stamp, scans[k].stamp);
    EXPECT_EQ(same.end, scans[k].end);
    ASSERT_EQ(same.points.size(), scans[k].points.size());
    for (std::size_t i = 0; i < same.points.size(); ++i) {
      ASSERT_EQ(same.points[i].x, scans[k].points[i].x);
      ASSERT_EQ(same.points[i].offset_ns, scans[k].points[i].offset_ns);
    }
    // The bag carries the same sweeps.
    EXPECT_EQ(from_bag[k].stamp, scans[k].stamp);
    EXPECT_EQ(from_bag[k].points.size(), scans[k].points.size());
  }
}

// T_world_body from the ground-truth file at one of its stamps (5 ms grid).
SE3 TruthAt(const Trajectory& truth, Stamp t) {
  const auto at = std::lower_bound(truth.stamps.begin(), truth.stamps.end(), t);
  EXPECT_TRUE(at != truth.stamps.end() && *at == t);
  return truth.poses[at - truth.stamps.begin()];
}

TEST(SequenceGenerator, HandheldSensorsAgreeWithTheTruth) {
  testing::TempDir dir;
  SimulationConfig config = SmallConfig();
  config.duration_s = 8.0;
  config.trajectory.motion = Motion::kHandheld;
  config.body_height_m = kHandheldBodyHeightM;
  config.lidar.keyframe_rate_hz = 2.0;
  config.imu.noise = ImuNoise{};  // exact signals: no noise, no bias
  auto summary = GenerateSequence(config, dir.path() / "seq");
  ASSERT_TRUE(summary.ok()) << summary.error();
  auto truth = ReadTumTrajectory((dir.path() / "seq/groundtruth.tum").string());
  auto calibration = ReadCalibrationFile(dir.path() / "seq/calibration_true.yaml");
  ASSERT_TRUE(truth.ok() && calibration.ok());
  const SE3 T_body_lidar = calibration->Find("lidar")->T_body_sensor;

  // The summary's figures against the written truth: the LiDAR's steps between consecutive scans (at
  // mid-sweep, on the truth's 5 ms grid) and the peak rate (central differences at 200 Hz).
  double rotation = 0.0, translation = 0.0;
  for (Stamp t = config.start_stamp + 550 * kMs; t + 100 * kMs <= config.start_stamp + 8000 * kMs;
       t += 500 * kMs) {
    const SE3 step =
        (TruthAt(*truth, t - 500 * kMs) * T_body_lidar).inverse() * TruthAt(*truth, t) * T_body_lidar;
    rotation = std::max(rotation, step.so3().Log().norm());
    translation = std::max(translation, step.translation().norm());
  }
  EXPECT_NEAR(summary->max_scan_rotation_rad, rotation, 1e-6);
  EXPECT_NEAR(summary->max_scan_translation_m, translation, 1e-6);
  EXPECT_GT(rotation, 15.0 * kDeg);
  EXPECT_GT(translation, 0.5);
  double peak = 0.0;
  for (std::size_t i = 1; i + 1 < truth->size(); ++i)
    peak =
        std::max(peak, (truth->poses[i - 1].so3().inverse() * truth->poses[i + 1].so3()).Log().norm() / 0.01);
  EXPECT_NEAR(summary->peak_body_rate_rad_s, peak, 0.5 * kDeg);
  EXPECT_GE(peak, 90.0 * kDeg);
  EXPECT_LT(summary->fit_position_error_m, 1e-4);
  EXPECT_LT(summary->fit_rotation_error_rad, 1e-3 * kDeg);

  // The IMU against the truth's central differences: the gyro, and the specific force R^T (a - g).
  auto reader = OpenDataset(dir.path() / "seq", DatasetOptions{});
  ASSERT_TRUE(reader.ok()) << reader.error();
  const std::vector<Measurement> all = ReadAll(**reader);
  double gyro_error = 0.0, accel_error = 0.0, still = 0.0;
  for (const Measurement& m : all) {
    const auto* imu = std::get_if<ImuSample>(&m.data);
    if (imu == nullptr || imu->stamp <= truth->stamps.front() || imu->stamp >= truth->stamps.back()) continue;
    const SE3 before = TruthAt(*truth, imu->stamp - 5 * kMs), now = TruthAt(*truth, imu->stamp),
              after = TruthAt(*truth, imu->stamp + 5 * kMs);
    const Eigen::Vector3d rate = (before.so3().inverse() * after.so3()).Log() / 0.01;
    const Eigen::Vector3d a = (after.translation() - 2 * now.translation() + before.translation()) / 25e-6;
    const Eigen::Vector3d f = now.rotation().transpose() * (a + Eigen::Vector3d(0, 0, kStandardGravity));
    gyro_error = std::max(gyro_error, (imu->gyro - rate).norm());
    accel_error = std::max(accel_error, (imu->acc - f).norm());
    if (imu->stamp < config.start_stamp + 900 * kMs)
      still =
          std::max({still, imu->gyro.norm(), (imu->acc - Eigen::Vector3d(0, 0, kStandardGravity)).norm()});
  }
  EXPECT_LT(gyro_error, 0.3 * kDeg);  // rad/s, of a peak of >= 90 deg/s
  EXPECT_LT(accel_error, 0.05);       // m/s^2, of a bounce's ~4
  // Standing still for static initialisation: what leaks out of the ramp through the spline fit (20 ms
  // knots) is ~3e-6; the vehicle's (0.1 s knots) ~5e-4.
  EXPECT_LT(still, 1e-5);

  // Every LiDAR point on the scene's surfaces at the truth's pose of its own time (range noise off): its
  // distance to the nearest triangle, by brute force (a distance along the beam would not do: at grazing
  // incidence a beam moved by the float rounding of the point meets another face).
  auto motion = MakeSimulationTrajectory(config);
  ASSERT_TRUE(motion.ok());
  auto scene =
      BuildScene({config.scene, config.seed, motion->scene_path, config.body_height_m, config.origin});
  ASSERT_TRUE(scene.ok());
  const TriangleMesh& mesh = scene->mesh;
  int scans = 0;
  double worst = 0.0;
  for (const Measurement& m : all) {
    const auto* scan = std::get_if<LidarScan>(&m.data);
    if (scan == nullptr) continue;
    ++scans;
    for (std::size_t i = 0; i < scan->points.size(); i += 41) {
      const LidarPoint& p = scan->points[i];
      const Stamp t = scan->stamp + p.offset_ns;
      // The truth between its 5 ms samples.
      const auto after = std::upper_bound(truth->stamps.begin(), truth->stamps.end(), t);
      const std::size_t j = after - truth->stamps.begin();
      const double s = double(t - truth->stamps[j - 1]) / double(truth->stamps[j] - truth->stamps[j - 1]);
      const Eigen::Vector3d world = Interpolate(truth->poses[j - 1], truth->poses[j], s) * T_body_lidar *
                                    Eigen::Vector3d(p.x, p.y, p.z);
      double nearest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3i& tri : mesh.triangles)
        nearest =
            std::min(nearest, uf::testing::PointTriangleDistance(world, mesh.vertices[tri[0]].cast<double>(),
                                                                 mesh.vertices[tri[1]].cast<double>(),
                                                                 mesh.vertices[tri[2]].cast<double>()));
      worst = std::max(worst, nearest);
    }
  }
  EXPECT_EQ(scans, 16);
  EXPECT_LT(worst, 2e-3);
}

TEST(SequenceGenerator, KeyframeRateAndMotionErrorsNameTheKey) {
  SimulationConfig config = SmallConfig();
  for (const auto& [rate, text] :
       {std::pair{20.0, std::string("got 20")}, {-1.0, "got -1"}, {std::nan(""), "got nan"}}) {
    config.lidar.keyframe_rate_hz = rate;
    const Status status = ValidateSimulationConfig(config);
    ASSERT_FALSE(status.ok()) << rate;
    EXPECT_EQ(status.message(),
              "sim.lidar.keyframe_rate_hz: must be in [0, sim.lidar.rate_hz = 10] (0: every "
              "sweep), " +
                  text);
  }
  config.lidar.keyframe_rate_hz = 10.0;
  EXPECT_TRUE(ValidateSimulationConfig(config).ok());

  config.trajectory.motion = Motion::kHandheld;
  EXPECT_TRUE(ValidateSimulationConfig(config).ok());
  config.trajectory.file = "poses.tum";
  const Status with_file = ValidateSimulationConfig(config);
  ASSERT_FALSE(with_file.ok());
  EXPECT_NE(with_file.message().find("sim.trajectory.motion: handheld"), std::string::npos)
      << with_file.message();
  EXPECT_NE(with_file.message().find("poses.tum"), std::string::npos) << with_file.message();

  testing::TempDir dir;
  config = SmallConfig();
  config.lidar.keyframe_rate_hz = 12.0;
  auto result = GenerateSequence(config, dir.path() / "out");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("sim.lidar.keyframe_rate_hz"), std::string::npos) << result.error();
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(Motion, NamesRoundTrip) {
  for (Motion motion : {Motion::kVehicle, Motion::kHandheld}) {
    Expected<Motion> parsed = ParseMotion(MotionName(motion));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, motion);
  }
  EXPECT_EQ(MotionName(Motion::kHandheld), "handheld");
  Expected<Motion> bad = ParseMotion("walking");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "unknown motion 'walking' (vehicle, handheld)");
}

}  // namespace
}  // namespace uf::sim
