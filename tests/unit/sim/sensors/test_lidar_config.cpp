// LidarConfig validation: each bad field gives an error naming the field and the value.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "lidar_test_support.h"
#include "odometry/sim/sensors/lidar_model.h"

namespace uf::sim {
namespace {

TEST(LidarConfig, DefaultsAndEveryPresetAreValid) {
  EXPECT_TRUE(ValidateLidarConfig(LidarConfig()).ok());
  for (const char* model : {"spinning16", "spinning32", "spinning64", "spinning128", "livox_avia"}) {
    LidarConfig config;
    config.model = model;
    EXPECT_TRUE(ValidateLidarConfig(config).ok()) << model;
  }
}

TEST(LidarConfig, BadFieldsAreNamedWithTheirValue) {
  struct Case {
    std::function<void(LidarConfig&)> spoil;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](LidarConfig& c) { c.model = "hdl99"; }, "lidar.model: "},
      {[](LidarConfig& c) { c.rate_hz = -5; }, "lidar.rate_hz: must be in [0.5, 100], got -5"},
      {[](LidarConfig& c) { c.rate_hz = 0.4; }, "lidar.rate_hz: must be in [0.5, 100], got 0.4"},
      {[](LidarConfig& c) { c.rate_hz = std::nan(""); }, "lidar.rate_hz: must be in [0.5, 100], got nan"},
      {[](LidarConfig& c) { c.horizontal_resolution_deg = 0; }, "lidar.horizontal_resolution_deg: "},
      {[](LidarConfig& c) { c.horizontal_resolution_deg = 45; }, "got 45"},
      {[](LidarConfig& c) { c.min_range_m = -1; }, "lidar.min_range_m: must be in [0, 10000), got -1"},
      {[](LidarConfig& c) { c.max_range_m = 0.4; },
       "lidar.max_range_m: must be in (min_range_m, 10000], got 0.4"},
      {[](LidarConfig& c) { c.range_noise_std_m = -0.1; },
       "lidar.range_noise_std_m: must be in [0, 10], got -0.1"},
      {[](LidarConfig& c) { c.dropout_probability = 1.5; },
       "lidar.dropout_probability: must be in [0, 1], got 1.5"},
      {[](LidarConfig& c) { c.threads = -2; }, "lidar.threads: must be >= 0 (0: all cores), got -2"},
  };
  for (const Case& test : cases) {
    LidarConfig config;
    test.spoil(config);
    const Status status = ValidateLidarConfig(config);
    ASSERT_FALSE(status.ok()) << test.expected;
    EXPECT_NE(status.message().find(test.expected), std::string::npos) << status.message();
  }
  LidarConfig unknown;
  unknown.model = "hdl99";
  EXPECT_NE(ValidateLidarConfig(unknown).message().find("'hdl99'"), std::string::npos);
}

TEST(LidarConfig, CreateRefusesABadConfig) {
  const Scene scene = test::BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = test::BriskSpline();
  LidarConfig config;
  config.rate_hz = 500;
  auto lidar = LidarSimulator::Create(config, caster, spline, SE3(), 1);
  ASSERT_FALSE(lidar.ok());
  EXPECT_NE(lidar.error().find("lidar.rate_hz"), std::string::npos);
}

TEST(LidarConfig, PeriodAndColumnsFollowTheConfig) {
  const Scene scene = test::BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = test::BriskSpline();
  LidarConfig config;
  config.rate_hz = 20.0;
  config.horizontal_resolution_deg = 0.2;
  const LidarSimulator lidar = std::move(LidarSimulator::Create(config, caster, spline, SE3(), 1).value());
  EXPECT_EQ(lidar.period(), 50'000'000);
  EXPECT_DOUBLE_EQ(lidar.period_s(), 0.05);
  EXPECT_EQ(lidar.columns(), 1800);
  EXPECT_EQ(lidar.rings(), 32);
}

}  // namespace
}  // namespace uf::sim
