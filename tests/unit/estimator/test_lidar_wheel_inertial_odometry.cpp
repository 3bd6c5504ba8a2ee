// LiDAR-wheel-inertial odometry (LWIO) end to end on short simulated sequences: the wheel factors join the
// window, the wheel scale is held where the LiDAR cannot see the forward motion and estimated where it can,
// bad wheel samples (NaN, stamps going back, gaps) are skipped with warnings, the wheel carries the
// translations the LiDAR holds more loosely (a corridor's axis), and a noisy encoder is not left out right
// after the initialization.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/unit/estimator/lio_sequence_run.h"

namespace uf::estimator {
namespace {

using testing::Joined;
using testing::LioRun;
using testing::RunLio;
using testing::Simulate;

TEST(LidarInertialOdometry, WheelFactorsJoinTheWindow) {
  uf::testing::TempDir dir;
  const LioRun run = RunLio(
      Simulate(dir, 4.0, "", /*wheel=*/true), [](ImuSample&) { return true; },
      [](WheelSample&) { return true; });
  EXPECT_TRUE(run.warnings.empty()) << Joined(run.warnings);
  // One factor per node interval: the first scan has one node, every later one a begin and an end node that
  // it shares with the previous scan: 40 scans, 41 nodes, 40 intervals.
  EXPECT_EQ(run.factors.wheel.added, 40);
  EXPECT_EQ(run.factors.wheel.skipped, 0);
  // The simulator's default encoder is ideal: the scale stays at 1 within a percent.
  EXPECT_NEAR(run.factors.wheel_scale, 1.0, 0.01);
  EXPECT_LT(run.ate_m, 0.03);  // as LIO's (measured 0.015 m without wheel)
}

TEST(LidarInertialOdometry, WheelScaleHeldWhereTheLidarDoesNotSeeTheForwardMotion) {
  // The corridor: featureless walls, LiDAR-degenerate along its axis; 1 s at rest, then driving off to
  // 1.2 m/s. The encoder is ideal, so the true scale is 1. While the vehicle drives off, the IMU is the only
  // other witness of the forward motion, and there an accelerometer bias error b looks like a scale of
  // 1 - b / a: a free scale took the error (0.21 after these 6 s, 0.22 after 6 s of the default 32-beam
  // corridor, before the observability test). The LiDAR constrains the forward position to several cm per
  // scan against the wheel's mm, so the scale is held at the truth. (The 6 s path is too straight for an
  // SE3-aligned ATE.)
  uf::testing::TempDir dir;
  const LioRun run = RunLio(
      Simulate(dir, 6.0, "", /*wheel=*/true, "corridor"), [](ImuSample&) { return true; },
      [](WheelSample&) { return true; }, /*evaluate=*/false);
  // One wheel factor per interval, joined or left out by the scheduling: the wheels' rest lets LIO start
  // (S) after 0.2 s instead of after the drive-off (M), and while the vehicle pulls away the window's speed
  // lags the wheel's until its gate shuts (31 intervals; 29 before the scans left their weak translations to
  // the wheel; the estimate lags as far without the stationary branch, all 60 joined: docs/METHOD.md
  // "Stationary branch").
  EXPECT_EQ(run.factors.wheel.added + run.factors.wheel.rejected, 60);
  EXPECT_EQ(run.factors.wheel_scale, 1.0);
}

TEST(LidarInertialOdometry, WheelScaleEstimatedWhereTheLidarSeesTheForwardMotion) {
  // Urban streets: the LiDAR pins the forward position to a few mm per scan, so the scale is free and
  // converges to the truth: a wheel radius 3 % too large makes the odometry report 1.03 times the speed,
  // true scale 1 / 1.03.
  uf::testing::TempDir dir;
  const LioRun run = RunLio(
      Simulate(dir, 6.0, "", /*wheel=*/true, "urban", 0.03), [](ImuSample&) { return true; },
      [](WheelSample&) { return true; });
  // Measured 0.9705 after the 6 s (1 s at rest, 5 s driving off), ATE 0.011 m; the same with the scale
  // free in every solve: it is observable throughout.
  EXPECT_NEAR(run.factors.wheel_scale, 1.0 / 1.03, 0.005);
  EXPECT_LT(run.ate_m, 0.03);  // as WheelFactorsJoinTheWindow's
}

TEST(LidarInertialOdometry, SkipsBadWheelSamplesWithWarnings) {
  uf::testing::TempDir dir;
  int count = 0;
  Stamp last = 0;
  const LioRun run = RunLio(
      Simulate(dir, 4.0, "", /*wheel=*/true), [](ImuSample&) { return true; },
      [&](WheelSample& w) {
        ++count;
        if (count == 60) w.linear_velocity.x() = std::nan("");  // NaN
        if (count == 90) w.stamp = last - 1'000'000;            // back in time
        if (count >= 120 && count < 140) return false;          // a 0.4 s gap at 50 Hz
        last = w.stamp;
        return true;
      });
  const std::string text = Joined(run.warnings);
  EXPECT_NE(text.find("not finite"), std::string::npos) << text;
  EXPECT_NE(text.find("not after"), std::string::npos) << text;
  EXPECT_NE(text.find("wheel factor at"), std::string::npos) << text;  // the intervals inside the gap
  EXPECT_GT(run.factors.wheel.skipped, 0);
  EXPECT_EQ(run.estimate.size(), 40u);
  EXPECT_LT(run.ate_m, 0.03);
}

// How far the estimate fell behind the truth along the way from its first keyframe to its last (the truth at
// the nearest of its own stamps), m: the distance the truth covered less the estimate's.
double LagAlongTheWay(const std::filesystem::path& folder, const Trajectory& estimate) {
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  if (!truth.ok() || estimate.poses.size() < 2) return std::numeric_limits<double>::infinity();
  const auto at = [&](Stamp t) {
    const auto it = std::lower_bound(truth->stamps.begin(), truth->stamps.end(), t);
    return truth->poses[std::min<std::size_t>(it - truth->stamps.begin(), truth->poses.size() - 1)]
        .translation();
  };
  const double travelled = (at(estimate.stamps.back()) - at(estimate.stamps.front())).norm();
  return travelled - (estimate.poses.back().translation() - estimate.poses.front().translation()).norm();
}

TEST(LidarInertialOdometry, TheWheelCarriesTheCorridorsAxisWhereTheLidarHoldsItLoosely) {
  // The straight corridor's start (1 s at rest, then pulling away to 1.2 m/s): its walls hold nothing along
  // the axis, yet planes fitted to the scan lines give the scans a hold there, and the estimate fell behind
  // the wheel. With lio.wheel_carries_weak_translations the scans leave that translation to the wheel.
  // The default 32-beam LiDAR, on which the rule was measured (docs/METHOD.md), and the planes through the
  // block's plain centroid (lo.map.neighbour_weight 1), which hold the axis as described: through the
  // default kernel centroid the LiDAR alone lags less (1.09 m) and the rule no longer shortens this 6 s lag
  // (1.27 m), while on the 60 s corridors it still pays (docs/METHOD.md "Factor-wise reliability
  // scheduling"). And the Huber scale of 0.5 m the rule was measured with (lo.huber_m): at the default 0.1 m
  // the scan-line planes' far points weigh less, the rule takes 13 of the 60 scans and the lag is 1.59 m with
  // it against 1.63 m without.
  uf::testing::TempDir dir;
  sim::SimulationConfig sequence;
  sequence.scene = "corridor";
  sequence.duration_s = 6.0;
  sequence.camera.enabled = sequence.gnss.enabled = false;
  const std::filesystem::path folder = dir.path() / "sequence";
  ASSERT_TRUE(sim::GenerateSequence(sequence, folder).ok());
  const auto run = [&](bool carries, int condensed_rounds) {
    return RunLio(
        folder, [](ImuSample&) { return true; }, [](WheelSample&) { return true; }, /*evaluate=*/false,
        [&](LidarOdometryConfig& config) {
          config.wheel_carries_weak_translations = carries;
          config.map.neighbour_weight = 1.0;
          config.huber_m = 0.5;
          config.condensed_lidar_rounds = condensed_rounds;
        });
  };
  const int rounds = LidarOdometryConfig{}.condensed_lidar_rounds;
  const LioRun with = run(true, rounds), without = run(false, rounds), uncondensed = run(true, 0);
  const double lag_with = LagAlongTheWay(folder, with.estimate),
               lag_without = LagAlongTheWay(folder, without.estimate),
               lag_uncondensed = LagAlongTheWay(folder, uncondensed.estimate);
  EXPECT_GT(with.factors.lidar_translations_to_wheel, 30);  // measured 53 of the 60 scans
  EXPECT_EQ(without.factors.lidar_translations_to_wheel, 0);
  // Measured 0.87 m behind after the 6 s against 1.79 m (what is left comes from each scan's first solve,
  // before the rule acts: docs/METHOD.md "Factor-wise reliability scheduling").
  EXPECT_LT(lag_with, 0.6 * lag_without) << lag_with << " m against " << lag_without << " m";
  // A window holding a scan taken through the projector is solved on the residuals, not condensed
  // (docs/METHOD.md "Sliding window and solve"), so the rule's run is the one without condensed factors
  // (measured equal to the micrometre). Condensed, the window slid along the axis with each new scan's
  // registration (lag 0.10 m here, but 20-80 % worse on the 60 s corridors).
  EXPECT_NEAR(lag_with, lag_uncondensed, 1e-3) << lag_with << " m against " << lag_uncondensed << " m";
}

TEST(LidarInertialOdometry, ANoisyEncoderJoinsFromTheStartOfATunnel) {
  // The degradation suite's tunnel (seed 4; the default 32-beam LiDAR, its axis free) with its noisy
  // encoder (0.3 rad/s per wheel sample, so the stationary branch never holds the standing second), 6 s:
  // right after the inertial initialization the window's velocity rests on nothing confirmed yet, and
  // scored against it the wheel's gate shut at 0.35 s and stayed shut (57 of 60 intervals left out, the
  // estimate 5.2 m behind after the 6 s). The wheel is scored from change_window_s after the first
  // predicted interval on: nothing left out, and the estimate as with the scheduling off (docs/METHOD.md
  // "Factor-wise reliability scheduling").
  uf::testing::TempDir dir;
  sim::SimulationConfig sequence;
  sequence.scene = "tunnel";
  sequence.seed = 4;
  sequence.duration_s = 6.0;
  sequence.camera.enabled = sequence.gnss.enabled = false;
  sequence.wheel.model.wheel_speed_noise_std = 0.3;
  const std::filesystem::path folder = dir.path() / "sequence";
  ASSERT_TRUE(sim::GenerateSequence(sequence, folder).ok());
  const auto run = [&](bool scheduled) {
    return RunLio(
        folder, [](ImuSample&) { return true; }, [](WheelSample&) { return true; }, /*evaluate=*/false,
        [&](LidarOdometryConfig& config) { config.wheel.schedule.enabled = scheduled; });
  };
  const LioRun scheduled = run(true), unscheduled = run(false);
  EXPECT_EQ(scheduled.factors.wheel.rejected, 0);
  const double lag = LagAlongTheWay(folder, scheduled.estimate),
               lag_unscheduled = LagAlongTheWay(folder, unscheduled.estimate);
  EXPECT_NEAR(lag, lag_unscheduled, 0.1) << lag << " m against " << lag_unscheduled << " m unscheduled";
  EXPECT_LT(lag, 1.5);  // measured 0.85 m after the 6 s (15 m driven), with and without the scheduling
}

}  // namespace
}  // namespace uf::estimator
