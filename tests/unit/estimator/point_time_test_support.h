// What the point-time check's tests and the re-check's share: the check run over scans, and simulated scans
// whose true times are replaced by times derived with a chosen convention (the simulator's spinning LiDAR
// sweeps clockwise from behind, lidar_model.h).
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "odometry/estimator/point_times/point_time_check.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sensors/lidar_model.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sim_trajectory.h"

namespace uf::estimator::point_time_testing {

inline constexpr AzimuthConvention kCcwBehind{AzimuthSweep::kCounterClockwise, SweepStart::kBehind};
inline constexpr AzimuthConvention kCwAhead{AzimuthSweep::kClockwise, SweepStart::kAhead};

// The check over `scans` until it is Done.
inline PointTimeCheckResult Check(const std::vector<LidarScan>& scans, const AzimuthConvention& current,
                                  const LidarOdometryConfig& config, const PointTimeCheckOptions& options) {
  Expected<PointTimeCheck> check = PointTimeCheck::Create(config, current, options);
  EXPECT_TRUE(check.ok()) << check.error();
  for (const LidarScan& scan : scans) {
    EXPECT_TRUE(check->Add(scan).ok());
    if (check->Done()) break;
  }
  return check->Decide();
}

// The score of `convention` among the result's, or nullptr.
inline const ConventionScore* ScoreOf(const PointTimeCheckResult& result,
                                      const AzimuthConvention& convention) {
  for (const ConventionScore& score : result.scores)
    if (score.convention == convention) return &score;
  return nullptr;
}

// The simulated wild scene driven through for 6 s (the simulator's default rig: spinning32 at 10 Hz).
inline sim::SimulationConfig WildDrive() {
  sim::SimulationConfig config;
  config.scene = "wild";
  config.duration_s = 6.0;
  return config;
}

// The same scene walked through with the sensor in hand for 9 s (turning at up to ~90 deg/s).
inline sim::SimulationConfig WildHandheld() {
  sim::SimulationConfig config = WildDrive();
  config.duration_s = 9.0;
  config.trajectory.motion = sim::Motion::kHandheld;
  config.body_height_m = sim::kHandheldBodyHeightM;
  return config;
}

// Scans of the simulation `Make()` starting every `every` sweeps (0.1 s each) from `from_s` on; their true
// times replaced by times derived by `derived`.
template <sim::SimulationConfig (*Make)()>
class SimulatedScansOf : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    config_ = new sim::SimulationConfig(Make());
    auto motion = sim::MakeSimulationTrajectory(*config_);
    ASSERT_TRUE(motion.ok()) << motion.error();
    motion_ = new sim::SimulationTrajectory(std::move(*motion));
    auto scene = sim::BuildScene(
        {config_->scene, config_->seed, motion_->poses, config_->body_height_m, config_->origin});
    ASSERT_TRUE(scene.ok()) << scene.error();
    scene_ = new sim::Scene(std::move(*scene));
    auto caster = sim::RayCaster::Create(*scene_);
    ASSERT_TRUE(caster.ok()) << caster.error();
    caster_ = new sim::RayCaster(std::move(*caster));
  }
  static void TearDownTestSuite() {
    delete caster_;
    delete scene_;
    delete motion_;
    delete config_;
  }

  // `turned`: the points in a LiDAR frame turned 180 deg about z (x backwards), where the sweep starts
  // ahead: the frame of the Newer College Ouster scans (below), whose true times fit clockwise from ahead.
  static std::vector<LidarScan> Scans(double from_s, int count, const AzimuthConvention& derived,
                                      bool turned = false, int every = 1) {
    auto lidar = sim::LidarSimulator::Create(config_->lidar.model, *caster_, motion_->spline,
                                             config_->lidar.placement.T_body_sensor, 3);
    EXPECT_TRUE(lidar.ok()) << lidar.error();
    std::vector<LidarScan> scans;
    for (int i = 0; i < count; ++i) {
      auto scan = lidar->Scan(motion_->begin + FromSeconds(from_s) + i * every * lidar->period());
      EXPECT_TRUE(scan.ok()) << scan.error();
      if (turned)
        for (LidarPoint& p : scan->points) {
          p.x = -p.x;
          p.y = -p.y;
        }
      DeriveAzimuthPointTimes(*scan, lidar->period(), derived);  // the true times stripped
      scans.push_back(std::move(*scan));
    }
    return scans;
  }

  static LidarOdometryConfig SimConfig() {  // configs/run-sim.yaml's lo: section
    LidarOdometryConfig config;
    config.input_voxel_m = 0.5;
    return config;
  }

  static inline sim::SimulationConfig* config_ = nullptr;
  static inline sim::SimulationTrajectory* motion_ = nullptr;
  static inline sim::Scene* scene_ = nullptr;
  static inline sim::RayCaster* caster_ = nullptr;
};

using SimulatedScans = SimulatedScansOf<WildDrive>;
using HandheldKeyframes = SimulatedScansOf<WildHandheld>;

}  // namespace uf::estimator::point_time_testing
