// LiDAR-inertial odometry (LIO) end to end on short simulated urban sequences: initialization (static and
// LiDAR-aided), accuracy against the simulator's ground truth, and bad IMU input (gaps, stamps going back,
// NaN samples) that must be bridged with warnings, never a NaN pose. With wheel factors (LWIO):
// test_lidar_wheel_inertial_odometry.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>

#include "tests/unit/estimator/lio_sequence_run.h"

namespace uf::estimator {
namespace {

using testing::Joined;
using testing::LioRun;
using testing::RunLio;
using testing::Simulate;

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
