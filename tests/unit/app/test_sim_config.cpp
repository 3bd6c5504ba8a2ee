// The sim: section (LoadConfigFile / EmitSimConfig): exact round trips, the documented profiles in configs/
// and the conventions (windows relative to the start, roll-pitch-yaw extrinsics, partial overrides).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "odometry/sim/sequence/simulation_config.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/app/config_samples.h"
#include "tests/unit/app/expect_same_config.h"
#include "viewer/app/config/config_file.h"

namespace uf::app {
namespace {

using sim::GnssQuality;
using sim::SimulationConfig;
using sim::TimeWindow;
using test::ExpectSameConfig;
using test::NonDefaultConfig;
using test::Pose;

// The sim: section of `file` over `base`.
Expected<SimulationConfig> LoadSimConfig(const std::string& file, SimulationConfig base = {}) {
  ConfigFile config;
  config.sim = std::move(base);
  Expected<ConfigFile> loaded = LoadConfigFile(file, std::move(config));
  if (!loaded) return loaded.status();
  return loaded->sim;
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
