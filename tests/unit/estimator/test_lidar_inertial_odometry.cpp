// LiDAR-inertial odometry (LIO, and LWIO with wheel factors) end to end on short simulated urban sequences:
// initialization (static and LiDAR-aided), accuracy against the simulator's ground truth, and bad IMU and
// wheel input (gaps, stamps going back, NaN samples) that must be bridged with warnings, never a NaN pose.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/lio_test_support.h"

namespace uf::estimator {
namespace {

// The simulator's default LiDAR mount (simulation_config.h): T_imu_lidar.
const SE3 kImuFromLidar(SO3(), Eigen::Vector3d(0, 0, 0.25));

// A short sequence of `scene` with LiDAR (16 beams, 0.4 deg) and IMU, and with `wheel` the wheel odometry
// (its radius off by `wheel_radius_error`, relative); `trajectory` (TUM) or the scene's default motion (1 s
// at rest, then driving off); the accelerometer clipped at `accel_saturation` (0: not).
std::filesystem::path Simulate(const uf::testing::TempDir& dir, double duration_s,
                               const std::string& trajectory = "", bool wheel = false,
                               const std::string& scene = "urban", double wheel_radius_error = 0,
                               double accel_saturation = 0) {
  sim::SimulationConfig config;
  config.scene = scene;
  config.imu.noise.accel_saturation = accel_saturation;
  config.duration_s = duration_s;
  config.wheel.model.radius_error = wheel_radius_error;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 0.4;
  config.camera.enabled = config.gnss.enabled = false;
  config.wheel.enabled = wheel;
  config.trajectory.file = trajectory;
  const std::filesystem::path out = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, out);
  EXPECT_TRUE(summary.ok()) << summary.error();
  return out;
}

struct LioRun {
  Trajectory estimate;
  std::vector<std::string> warnings;
  std::string initialization;
  InitializationRecord init;
  SensorFactorStats factors;
  double ate_m = std::numeric_limits<double>::infinity();
};

// Runs LIO over the folder; `edit_imu` may change or drop (return false) each IMU sample first. With
// `edit_wheel`, LWIO: the wheel stream goes in too (each sample through it first), with the wheel's
// T_body_sensor from the dataset (the body is the IMU).
LioRun RunLio(
    const std::filesystem::path& folder,
    const std::function<bool(ImuSample&)>& edit_imu = [](ImuSample&) { return true; },
    const std::function<bool(WheelSample&)>& edit_wheel = nullptr, bool evaluate = true,
    const std::function<void(LidarOdometryConfig&)>& edit_config = nullptr) {
  LioRun run;
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  LidarOdometryConfig config = testing::SimulatedLioConfig(kImuFromLidar);
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

// The admitted state against the ground truth at its stamp: the angle between the estimated and the true
// "up" seen in the imu frame (deg), and the difference of the velocities seen in the imu frame (m/s); both
// free of the world's yaw.
struct InitErrors {
  double gravity_deg = std::numeric_limits<double>::infinity();
  double velocity_mps = std::numeric_limits<double>::infinity();
};
InitErrors InitializationErrors(const InitializationRecord& init, const std::filesystem::path& folder) {
  InitErrors out;
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  const Stamp h = 5'000'000;
  const auto T = truth->PoseAt(init.admitted_at), before = truth->PoseAt(init.admitted_at - h),
             after = truth->PoseAt(init.admitted_at + h);
  if (!init.admitted || !T || !before || !after) return out;
  const Eigen::Vector3d up(0, 0, 1);
  const double cosine = (T->so3().inverse() * up).dot(init.R_world_imu.inverse() * up);
  out.gravity_deg = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  const Eigen::Vector3d v_true = (after->translation() - before->translation()) / ToSeconds(2 * h);
  out.velocity_mps = (T->so3().inverse() * v_true - init.R_world_imu.inverse() * init.velocity).norm();
  return out;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

TEST(LidarInertialOdometry, StaticStartInitializesAndTracks) {
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0);
  const LioRun run = RunLio(folder);
  // S after the second scan: the IMU at rest and the LiDAR still, 0.2 s after the first IMU sample.
  EXPECT_EQ(run.init.mode, InitMode::kStatic) << run.initialization << "\n" << Joined(run.warnings);
  EXPECT_EQ(run.initialization.rfind("S (static) after 0.2 s", 0), 0u) << run.initialization;
  EXPECT_NEAR(run.init.latency_s, 0.2, 1e-9);
  EXPECT_EQ(run.init.attempts, 1);
  const InitErrors errors = InitializationErrors(run.init, folder);
  EXPECT_LT(errors.gravity_deg, 0.1);  // measured 0.05
  EXPECT_LT(errors.velocity_mps, 0.005);
  EXPECT_EQ(run.estimate.size(), 40u);
  EXPECT_TRUE(run.warnings.empty()) << Joined(run.warnings);
  // Measured 0.015 m over the 4 s (1 s at rest, then 3 s accelerating to ~4 m/s, 16 sparse beams).
  EXPECT_LT(run.ate_m, 0.03);
}

// lio.imu_deskew on the static start above: the run is as clean and as accurate (the drive's motion within a
// sweep is small; the correction's geometry is tested in test_imu_sweep_correction.cpp).
TEST(LidarInertialOdometry, ImuCorrectionWithinTheSweepTracksAsWell) {
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0);
  const LioRun run = RunLio(
      folder, [](ImuSample&) { return true; }, nullptr, true,
      [](LidarOdometryConfig& config) { config.imu_deskew = true; });
  EXPECT_EQ(run.init.mode, InitMode::kStatic) << run.initialization;
  EXPECT_EQ(run.estimate.size(), 40u);
  EXPECT_TRUE(run.warnings.empty()) << Joined(run.warnings);
  EXPECT_LT(run.ate_m, 0.03);  // measured 0.016 m
}

TEST(LidarInertialOdometry, MovingStartInitializesWithTheLidar) {
  // 5 m/s along a gentle S-curve with a vertical wobble from the first instant.
  uf::testing::TempDir dir;
  std::ofstream tum(dir.File("moving.tum"));
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.1 * k, yaw = 0.15 * std::sin(0.8 * t);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    tum << 100 + t << " " << 5 * t << " " << 3 * std::sin(0.4 * t) << " " << 0.3 * std::sin(1.5 * t) << " "
        << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << "\n";
  }
  tum.close();
  const LioRun run = RunLio(Simulate(dir, 5.0, dir.File("moving.tum")));
  EXPECT_EQ(run.init.mode, InitMode::kLidarAided) << run.initialization << "\n" << Joined(run.warnings);
  // Measured 0.013 m: the first LO window is rougher on a moving start (its first sweep is mapped as if at
  // rest), the alignment's gravity comes out 7 % short and is rescaled.
  EXPECT_LT(run.ate_m, 0.03);
}

TEST(LidarInertialOdometry, KeyframesFromBeforeTheInitializationLeaveInTheGravityAlignedWorld) {
  // Driving off at 5 m/s on a road banked by 4 deg (KITTI raw 0009 starts so): the LO frame before the
  // initialization is the first IMU pose's, tilted by the bank. Every keyframe, the ones that left the window
  // before the alignment included, must come out with the true tilt (before, those came out level and the
  // trajectory jumped by 4 deg of roll at the alignment).
  uf::testing::TempDir dir;
  std::ofstream tum(dir.File("banked.tum"));
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.1 * k, yaw = 0.15 * std::sin(0.8 * t);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(4.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()));
    tum << 100 + t << " " << 5 * t << " " << 3 * std::sin(0.4 * t) << " 0 " << q.x() << " " << q.y() << " "
        << q.z() << " " << q.w() << "\n";
  }
  tum.close();
  const std::filesystem::path folder = Simulate(dir, 5.0, dir.File("banked.tum"));
  const LioRun run = RunLio(folder);
  ASSERT_TRUE(run.init.admitted) << run.initialization << "\n" << Joined(run.warnings);
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  ASSERT_TRUE(truth.ok());
  int before_alignment = 0;
  for (std::size_t i = 0; i < run.estimate.size(); ++i) {
    const std::optional<SE3> T = truth->PoseAt(run.estimate.stamps[i]);
    if (!T) continue;
    // The angle between the true and the estimated "up", both seen in the imu frame (free of the yaw).
    const Eigen::Vector3d up(0, 0, 1);
    const double cosine = (T->so3().inverse() * up).dot(run.estimate.poses[i].so3().inverse() * up);
    const double tilt_error_deg = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi;
    EXPECT_LT(tilt_error_deg, 1.0) << "keyframe at " << ToSeconds(run.estimate.stamps[i]) << " s";
    before_alignment += run.estimate.stamps[i] < run.init.admitted_at;
  }
  EXPECT_GE(before_alignment, 5);  // the case this is about: keyframes that had left before the alignment
}

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
  EXPECT_EQ(run.factors.wheel.added, 60);
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

TEST(LidarInertialOdometry, BridgesImuGapsAndSkipsBadSamples) {
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0);
  Stamp first = 0, previous = 0;
  const LioRun run = RunLio(folder, [&](ImuSample& s) {
    if (first == 0) first = s.stamp;
    const double t = ToSeconds(s.stamp - first);
    if (t > 2.0 && t < 2.3) return false;                    // a 0.3 s gap while driving
    if (std::abs(t - 1.5) < 1e-3) s.acc.x() = std::nan("");  // one NaN sample
    if (std::abs(t - 3.0) < 1e-3) s.stamp = previous;        // one duplicated stamp
    previous = s.stamp;
    return true;
  });
  const std::string warnings = Joined(run.warnings);
  EXPECT_NE(warnings.find("bridged with the constant-velocity prior"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("not finite"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("not after"), std::string::npos) << warnings;
  EXPECT_EQ(run.estimate.size(), 40u);
  EXPECT_LT(run.ate_m, 0.03);  // measured 0.016 m
}

// Writes a TUM trajectory of `seconds` at 10 Hz from time 100: position p(t) and yaw(t).
std::string WriteTum(const uf::testing::TempDir& dir, const std::string& name, double seconds,
                     const std::function<Eigen::Vector3d(double)>& position,
                     const std::function<double(double)>& yaw) {
  std::ofstream tum(dir.File(name));
  for (int k = 0; k <= static_cast<int>(std::lround(seconds * 10)); ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector3d p = position(t);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw(t), Eigen::Vector3d::UnitZ()));
    tum << 100 + t << " " << p.x() << " " << p.y() << " " << p.z() << " " << q.x() << " " << q.y() << " "
        << q.z() << " " << q.w() << "\n";
  }
  return dir.File(name);
}

TEST(LidarInertialOdometry, SlowStartDefersThenInitializesWithTheLidar) {
  // Creeping at 0.3 m/s down the street from the first instant, steady: the IMU sees no excitation (a steady
  // velocity is invisible to it), the LiDAR sees the motion, so S is refused; M waits (A) until the window
  // is long enough for its gravity.
  uf::testing::TempDir dir;
  const std::string tum = WriteTum(
      dir, "slow.tum", 6.0, [](double t) { return Eigen::Vector3d(0.3 * t, 0.05 * std::sin(0.5 * t), 0); },
      [](double t) { return 0.02 * std::sin(0.5 * t); });
  const std::filesystem::path folder = Simulate(dir, 5.0, tum);
  const LioRun run = RunLio(
      folder, [](ImuSample&) { return true; }, nullptr, /*evaluate=*/false);
  EXPECT_EQ(run.init.mode, InitMode::kLidarAided) << run.initialization << "\n" << Joined(run.warnings);
  EXPECT_GE(run.init.deferred, 3) << run.initialization;
  EXPECT_NE(Joined(run.warnings).find("LIO initialization deferred at"), std::string::npos);
  EXPECT_NE(Joined(run.warnings).find("not at rest (the poses move at"), std::string::npos);
  const InitErrors errors = InitializationErrors(run.init, folder);
  EXPECT_LT(errors.gravity_deg, 0.5) << run.initialization;
  EXPECT_LT(errors.velocity_mps, 0.05) << run.initialization;
}

TEST(LidarInertialOdometry, RejectsAWrongGravityAndRetries) {
  // A static start whose accelerometer reads a specific force tilted by 3 degrees for its first 0.15 s (a
  // transient): S's mean specific force, and with it its gravity, is off by 2 degrees after two scans; the
  // velocity changes of the IMU do not fit it, so the check rejects it, and a later attempt, with the
  // oldest scans dropped, is admitted.
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0);
  Stamp first = 0;
  const SO3 tilt = SO3::Exp(Eigen::Vector3d(3.0 * std::numbers::pi / 180.0, 0, 0));
  const LioRun run = RunLio(folder, [&](ImuSample& s) {
    if (first == 0) first = s.stamp;
    if (s.stamp - first < 150'000'000) s.acc = tilt * s.acc;
    return true;
  });
  EXPECT_EQ(run.init.mode, InitMode::kStatic) << run.initialization << "\n" << Joined(run.warnings);
  EXPECT_GE(run.init.rejected, 1) << run.initialization;
  ASSERT_FALSE(run.init.rejections.empty());
  EXPECT_NE(run.init.rejections.front().find("velocity changes do not fit"), std::string::npos)
      << run.init.rejections.front();
  EXPECT_NE(Joined(run.warnings).find("LIO initialization rejected at"), std::string::npos);
  EXPECT_LT(run.init.latency_s, 1.0) << run.initialization;
  // Measured: rejected at 0.2, 0.3 and 0.4 s (chi-square 5.8, 5.7, 4.8 per dof), admitted at 0.5 s within
  // 0.34 deg (0.05 s of the transient are still in the window: below what the check resolves with the
  // estimator's IMU noise, 10x the simulated IMU's). Admitted at the first try, the error would be 2 deg.
  EXPECT_LT(InitializationErrors(run.init, folder).gravity_deg, 0.5) << run.initialization;
  EXPECT_LT(run.ate_m, 0.03);
}

TEST(LidarInertialOdometry, AnImuGapDuringTheInitializationRestartsItsWindow) {
  // A static start whose IMU is silent from 0.12 to 0.28 s: the windows across the gap cannot be
  // preintegrated, so the attempts defer and the window starts again after the gap; S follows there.
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0);
  Stamp first = 0;
  const LioRun run = RunLio(folder, [&](ImuSample& s) {
    if (first == 0) first = s.stamp;
    const Stamp t = s.stamp - first;
    return t < 120'000'000 || t > 280'000'000;
  });
  EXPECT_EQ(run.init.mode, InitMode::kStatic) << run.initialization << "\n" << Joined(run.warnings);
  // Measured: S at 0.5 s, after the deferrals across the gap. Without the restart of the window every attempt
  // failed on the gap until the vehicle drove off (then M at 2.1 s).
  EXPECT_GE(run.init.deferred, 2) << run.initialization;
  EXPECT_GT(run.init.latency_s, 0.3);
  EXPECT_LT(run.init.latency_s, 1.0) << run.initialization;
  EXPECT_LT(InitializationErrors(run.init, folder).gravity_deg, 0.2) << run.initialization;
}

TEST(LidarInertialOdometry, SaturatingAccelerometerNeverInitializesAndStaysFinite) {
  // An accelerometer clipped at 8 m/s^2 per axis reads 8 instead of gravity at rest: neither S (its mean
  // specific force is not gravity) nor M (the free gravity estimate is 8 m/s^2) is admitted, each scan
  // tries once more, the first rejection is a warning and the rest are counted; the run stays LiDAR-only and
  // every pose finite.
  uf::testing::TempDir dir;
  const std::filesystem::path folder = Simulate(dir, 4.0, "", false, "urban", 0, /*accel_saturation=*/8.0);
  const LioRun run = RunLio(folder);
  EXPECT_FALSE(run.init.admitted) << run.initialization;
  EXPECT_TRUE(run.initialization.empty());
  EXPECT_EQ(run.init.attempts, 39);  // one per scan after the first
  EXPECT_GT(run.init.rejected, 0);
  EXPECT_EQ(run.init.attempts, run.init.deferred + run.init.rejected);
  EXPECT_NE(Joined(run.warnings).find("LIO initialization rejected at"), std::string::npos)
      << Joined(run.warnings);
  EXPECT_EQ(run.estimate.size(), 40u);
  EXPECT_LT(run.ate_m, 0.05);
}

TEST(LidarInertialOdometry, ConfigRejectsAnInitWindowAsLongAsTheWindow) {
  LidarOdometryConfig config;
  config.use_imu = true;
  config.init.min_scans = config.window_size;
  const Status status = config.Validate();
  EXPECT_NE(status.message().find("lio.init.min_scans"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace uf::estimator
