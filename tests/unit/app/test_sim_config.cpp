// LoadSimConfig / EmitSimConfig: exact round trips, the documented profiles in configs/ and the
// conventions (windows relative to the start, roll-pitch-yaw extrinsics, partial overrides).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "odometry/sim/sequence/simulation_config.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/app/expect_same_sim_config.h"
#include "viewer/app/config/sim_config.h"

namespace uf::app {
namespace {

using sim::GnssQuality;
using sim::SimulationConfig;
using sim::TimeWindow;
using test::ExpectSameConfig;

// [begin_s, end_s] after `start`, exact nanoseconds.
TimeWindow Window(Stamp start, Stamp begin_ns, Stamp end_ns) { return {start + begin_ns, start + end_ns}; }

SE3 Pose(double rx, double ry, double rz, double x, double y, double z) {
  return SE3(SO3::Exp(Eigen::Vector3d(rx, ry, rz)), Eigen::Vector3d(x, y, z));
}

// A value other than the default in every field, with awkward doubles (1/3, 0.1 + 0.2, 1e-300, 2^-1074).
SimulationConfig NonDefaultConfig() {
  SimulationConfig c;
  c.scene = "weird \"scene\" \\ name: #1";
  c.seed = 18446744073709551615ULL;
  c.duration_s = 1.0 / 3.0;
  c.start_stamp = 1'234'567'890'123'456'789;
  c.trajectory = {.file = "/data/path with spaces/poses.txt",
                  .format = "kitti",
                  .kitti_rate_hz = 9.5,
                  .knot_spacing_s = 0.1 + 0.2};
  c.body_height_m = 1e-300;
  c.ground_truth_rate_hz = 123.456;
  c.origin = {-33.8688197, 151.2092955, -12.5};
  c.threads = 3;
  c.write_bag = true;
  const Stamp s = c.start_stamp;

  c.imu.enabled = false;
  c.imu.rate_hz = 400.5;
  c.imu.noise = {1.1e-3, 2.2e-4, 3.3e-5, 4.4e-6, {0.01, -0.02, 0.03}, {-1e-4, 2e-4, 4.9406564584124654e-324},
                 160.0,  8.7};

  c.lidar.enabled = false;
  c.lidar.model = {.model = "livox_avia",
                   .rate_hz = 12.5,
                   .horizontal_resolution_deg = 0.35,
                   .min_range_m = 0.75,
                   .max_range_m = 150.0,
                   .range_noise_std_m = 0.033,
                   .dropout_probability = 0.125};
  c.lidar.placement = {Pose(0.1, -0.2, 0.3, 0.11, -0.22, 0.33), 0.1, {1.0, -2.0, 3.0}, {0.01, 0.02, -0.03}};

  sim::CameraConfig& m = c.camera.model;
  c.camera.enabled = false;
  m.width = 1280, m.height = 720;
  m.fx = 701.5, m.fy = 702.25, m.cx = 640.125, m.cy = 359.75;
  m.k1 = -0.28, m.k2 = 0.07, m.p1 = 1e-4, m.p2 = -2e-4, m.k3 = 0.001;
  m.rate_hz = 30.0, m.noise_std_dn = 2.5, m.supersampling = 3;
  m.sun_direction_world = {-0.5, 0.25, 1.0 / 7.0};
  m.ambient = 0.2, m.exposure = 1.7, m.textured = false;
  m.darkness = {Window(s, 1'000'000'001, 2'500'000'000), Window(s, -500'000'000, 1)};
  m.exposure_changes = {{Window(s, 3'000'000'000, 4'000'000'000), 2.0}, {Window(s, 5, 6), 0.3}};
  m.occlusions = {Window(s, 7'123'456'789, 8'000'000'000)};
  c.camera.placement = {sim::ForwardLookingCamera({0.5, -0.1, 0.2}) * Pose(0.01, 0.02, 0.03, 0, 0, 0),
                        -0.02,
                        {0.5, 0.5, -0.5},
                        {0, 0, 0.01}};

  c.wheel.enabled = false;
  c.wheel.model.rate_hz = 100.0;
  c.wheel.model.wheel_radius_m = 0.2;
  c.wheel.model.baseline_m = 0.6;
  c.wheel.model.radius_error = 0.01;
  c.wheel.model.baseline_error = -0.02;
  c.wheel.model.encoder_resolution_ticks = 4096;
  c.wheel.model.wheel_speed_noise_std = 0.05;
  c.wheel.model.slips = {{Window(s, 10'000'000'000, 12'000'000'000), 0.3}, {Window(s, 1, 2), -1.0}};
  c.wheel.model.floats = {Window(s, 20'000'000'000, 20'500'000'000)};
  c.wheel.placement = {Pose(0, 0, 0.5, -0.4, 0.0, -0.6), 0.005, {0, 0, 1}, {0.1, 0, 0}};

  c.gnss.enabled = false;
  c.gnss.model.rate_hz = 10.0;
  c.gnss.model.quality = GnssQuality::kRtkFloat;
  c.gnss.model.quality_changes = {{Window(s, 0, 5'000'000'000), GnssQuality::kRtkFixed},
                                  {Window(s, 6'000'000'000, 7'000'000'000), GnssQuality::kSingle}};
  c.gnss.model.outages = {Window(s, 30'000'000'000, 40'000'000'000)};
  c.gnss.model.multipath = {{Window(s, 41'000'000'000, 45'000'000'000), {3.0, -4.0, 0.5}}};
  c.gnss.model.rtk_fixed = {0.01, 0.03, 1.0};
  c.gnss.model.rtk_float = {0.2, 0.4, 8.0};
  c.gnss.model.single = {2.0, 4.0, 60.0};
  c.gnss.placement = {Pose(0, 0, 0, 0.1, 0.2, 0.9), 0.25, {0, 0, 0}, {0, 0, 0.1}};
  return c;
}

Expected<SimulationConfig> LoadText(const testing::TempDir& dir, const std::string& text,
                                    SimulationConfig base = {}) {
  return LoadSimConfig(dir.Write("sim.yaml", text), std::move(base));
}

TEST(SimConfig, EmitThenLoadGivesTheSameConfigExactly) {
  testing::TempDir dir;
  const SimulationConfig original = NonDefaultConfig();
  const std::string text = EmitSimConfig(original);
  Expected<SimulationConfig> loaded = LoadText(dir, text);
  ASSERT_TRUE(loaded.ok()) << loaded.error() << "\n" << text;
  ExpectSameConfig(*loaded, original);
  EXPECT_EQ(EmitSimConfig(*loaded), text);

  // The defaults too, and the emitted file overrides every field of a different base.
  const std::string defaults = EmitSimConfig(SimulationConfig{});
  loaded = LoadText(dir, defaults, original);
  ASSERT_TRUE(loaded.ok()) << loaded.error() << "\n" << defaults;
  ExpectSameConfig(*loaded, SimulationConfig{});
}

TEST(SimConfig, EmittedWindowsAreRelativeToTheStart) {
  SimulationConfig config;
  config.start_stamp = 1'700'000'000'250'000'000;
  config.camera.model.darkness = {{config.start_stamp + 1'500'000'000, config.start_stamp + 2'000'000'001}};
  const std::string text = EmitSimConfig(config);
  EXPECT_NE(text.find("start_time_s: 1700000000.25\n"), std::string::npos) << text;
  EXPECT_NE(text.find("darkness: [[1.5, 2.000000001]]\n"), std::string::npos) << text;
}

TEST(SimConfig, WindowsAreResolvedAfterTheStartWhereverItStands) {
  testing::TempDir dir;
  Expected<SimulationConfig> loaded =
      LoadText(dir,
               "sim:\n"
               "  camera: {darkness: [[1.5, 2]], occlusions: []}\n"
               "  gnss:\n"
               "    multipath: [{window: [0, 0.000000001], offset_m: [1, 2, 3]}]\n"
               "  start_time_s: 100.25\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  ASSERT_EQ(loaded->camera.model.darkness.size(), 1u);
  EXPECT_EQ(loaded->start_stamp, 100'250'000'000);
  EXPECT_EQ(loaded->camera.model.darkness[0].begin, 101'750'000'000);
  EXPECT_EQ(loaded->camera.model.darkness[0].end, 102'250'000'000);
  ASSERT_EQ(loaded->gnss.model.multipath.size(), 1u);
  EXPECT_EQ(loaded->gnss.model.multipath[0].first.begin, 100'250'000'000);
  EXPECT_EQ(loaded->gnss.model.multipath[0].first.end, 100'250'000'001);
  EXPECT_EQ(loaded->gnss.model.multipath[0].second, Eigen::Vector3d(1, 2, 3));
}

TEST(SimConfig, KeysNotGivenKeepTheBaseAndGivenListsReplaceIt) {
  testing::TempDir dir;
  const SimulationConfig base = NonDefaultConfig();
  Expected<SimulationConfig> loaded = LoadText(
      dir, "dataset: {format: kitti}\nsim:\n  lidar: {rate_hz: 20}\n  camera: {darkness: []}\n", base);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  SimulationConfig expected = base;
  expected.lidar.model.rate_hz = 20.0;
  expected.camera.model.darkness.clear();
  ExpectSameConfig(*loaded, expected);

  // No sim section, an empty file, an empty section: the base.
  for (const char* text : {"calibration: {anything: [1, 2]}\n", "", "sim:\n", "sim:\n  imu:\n"}) {
    loaded = LoadText(dir, text, base);
    ASSERT_TRUE(loaded.ok()) << text << ": " << loaded.error();
    ExpectSameConfig(*loaded, base);
  }
}

TEST(SimConfig, RollPitchYawIsRzRyRxInDegrees) {
  testing::TempDir dir;
  Expected<SimulationConfig> loaded =
      LoadText(dir,
               "sim:\n"
               "  lidar:\n"
               "    extrinsic: {translation_m: [1, 2, 3], rotation_rpy_deg: [10, 20, 30]}\n"
               "  camera:\n"
               "    extrinsic: {rotation_rpy_deg: [-90, 0, -90]}\n"
               "  wheel:\n"
               "    extrinsic: {rotation_rpy_deg: [0, 0, 90]}\n"
               "  gnss:\n"
               "    extrinsic: {translation_m: [0.5, 0, 1]}\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  constexpr double kDeg = std::numbers::pi / 180.0;
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(30 * kDeg, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(20 * kDeg, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_LE((loaded->lidar.placement.T_body_sensor.rotation() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(loaded->lidar.placement.T_body_sensor.translation(), Eigen::Vector3d(1, 2, 3));
  // The forward-looking camera mount exactly (optical axis z along body x, image x along -body y); the
  // translation keeps the base's value.
  const SE3 forward =
      sim::ForwardLookingCamera(SimulationConfig{}.camera.placement.T_body_sensor.translation());
  EXPECT_EQ(loaded->camera.placement.T_body_sensor.matrix(), forward.matrix());
  // Yaw 90: the sensor's x axis is the body's y axis (p_body = T_body_sensor p_sensor).
  EXPECT_EQ(loaded->wheel.placement.T_body_sensor.rotation() * Eigen::Vector3d::UnitX(),
            Eigen::Vector3d::UnitY());
  EXPECT_EQ(loaded->gnss.placement.T_body_sensor.rotation(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(loaded->gnss.placement.T_body_sensor.translation(), Eigen::Vector3d(0.5, 0, 1));
}

TEST(SimConfig, MatrixExtrinsicIsRowMajor) {
  testing::TempDir dir;
  Expected<SimulationConfig> loaded = LoadText(
      dir, "sim:\n  lidar:\n    extrinsic: {matrix: [0, -1, 0, 1,  1, 0, 0, 2,  0, 0, 1, 3,  0, 0, 0, 1]}\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  Eigen::Matrix4d expected;
  expected << 0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1;
  EXPECT_EQ(loaded->lidar.placement.T_body_sensor.matrix(), expected);
}

TEST(SimConfig, ProfilesInConfigsLoadAndSimYamlIsTheDefaults) {
  const std::string configs = std::string(UF_SOURCE_DIR) + "/configs/";
  Expected<SimulationConfig> defaults = LoadSimConfig(configs + "sim.yaml", NonDefaultConfig());
  ASSERT_TRUE(defaults.ok()) << defaults.error();
  // The documented rpy of the camera mount gives ForwardLookingCamera's matrix to rounding at most.
  ExpectSameConfig(*defaults, SimulationConfig{}, 1e-15);
  EXPECT_TRUE(sim::ValidateSimulationConfig(*defaults).ok());

  Expected<SimulationConfig> degraded = LoadSimConfig(configs + "sim-degraded.yaml");
  ASSERT_TRUE(degraded.ok()) << degraded.error();
  const Status valid = sim::ValidateSimulationConfig(*degraded);
  EXPECT_TRUE(valid.ok()) << valid.message();
  EXPECT_EQ(degraded->lidar.placement.stamp_delay_s, 0.1);
  EXPECT_NEAR(degraded->lidar.placement.rotation_error_deg.norm(), 3.0, 1e-12);
  EXPECT_FALSE(degraded->camera.model.darkness.empty());
  EXPECT_FALSE(degraded->camera.model.occlusions.empty());
  EXPECT_FALSE(degraded->wheel.model.slips.empty());
  EXPECT_FALSE(degraded->gnss.model.outages.empty());
  EXPECT_FALSE(degraded->gnss.model.multipath.empty());
}

TEST(SimConfig, GnssQualityNamesRoundTrip) {
  for (GnssQuality quality : {GnssQuality::kSingle, GnssQuality::kRtkFloat, GnssQuality::kRtkFixed}) {
    Expected<GnssQuality> parsed = ParseGnssQuality(GnssQualityName(quality));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, quality);
  }
  EXPECT_EQ(GnssQualityName(GnssQuality::kRtkFixed), "rtk_fixed");
  EXPECT_FALSE(ParseGnssQuality("fixed").ok());
}

}  // namespace
}  // namespace uf::app
