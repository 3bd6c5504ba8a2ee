// GNSS factors inside the windows (providers/gnss_provider.h) end to end on short simulated urban sequences:
// WGIO (wheel-inertial) and LWGIO (LiDAR-inertial with wheel) against the simulator's ground truth in ENU,
// without any alignment after the run (the estimator's own georeference); injected 20 m multipath jumps
// rejected by the integrity check; bad fixes (no fix, NaN, unknown covariance, kilometre jumps, stamps going
// back) counted and skipped, never a NaN pose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "odometry/estimator/inertial_odometry/inertial_odometry.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/geo_trajectory_file.h"
#include "odometry/io/trajectory_file.h"
#include "odometry/sim/sequence/sequence_generator.h"
#include "tests/support/temp_dir.h"

namespace uf::estimator {
namespace {

const GeodeticOrigin kSimOrigin = sim::SimulationConfig{}.origin;

// The default urban drive (1 s at rest, then off at ~8 m/s) with the IMU, the wheel and 5 Hz GNSS of the
// given quality; the 16-beam LiDAR only when asked.
std::filesystem::path Simulate(const uf::testing::TempDir& dir, double duration_s, sim::GnssQuality quality,
                               bool lidar) {
  sim::SimulationConfig config;
  config.duration_s = duration_s;
  config.camera.enabled = false;
  config.lidar.enabled = lidar;
  config.lidar.model.model = "spinning16";
  config.lidar.model.horizontal_resolution_deg = 0.4;
  config.gnss.model.quality = quality;
  const std::filesystem::path out = dir.path() / "sequence";
  auto summary = sim::GenerateSequence(config, out);
  EXPECT_TRUE(summary.ok()) << summary.error();
  return out;
}

const StreamInfo* FindStream(const DatasetDescription& description, SensorKind kind) {
  for (const StreamInfo& stream : description.streams)
    if (stream.kind == kind) return &stream;
  return nullptr;
}

struct GeoRun {
  Trajectory estimate;  // T_world_imu
  std::vector<std::string> warnings;
  SensorFactorStats factors;
  std::optional<Georeference> georef;
  std::vector<GnssCheck> checks;  // the fixes the keyframes carry (reliability scores)
};

// Feeds every measurement to `window` (InertialOdometry or LidarOdometry); `edit_fix` may change or drop
// (return false) each fix first.
template <typename Window>
GeoRun Run(Window& window, DatasetReader& reader, const std::function<bool(GnssFix&)>& edit_fix) {
  const Status read = ForEachMeasurement(reader, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data)) {
      if constexpr (std::is_same_v<Window, LidarOdometry>) return window.AddScan(*scan);
    }
    if (const auto* sample = std::get_if<ImuSample>(&m.data)) return window.AddImu(*sample);
    if (const auto* wheel = std::get_if<WheelSample>(&m.data)) return window.AddWheel(*wheel);
    if (auto* fix = std::get_if<GnssFix>(&m.data); fix && edit_fix(*fix)) return window.AddGnss(*fix);
    return Status();
  });
  EXPECT_TRUE(read.ok()) << read.message();
  window.Finish();
  GeoRun run;
  for (const Keyframe& k : window.TakeFinished()) {
    EXPECT_TRUE(k.T_world_body.matrix().allFinite()) << ToSeconds(k.stamp);
    run.estimate.stamps.push_back(k.stamp);
    run.estimate.poses.push_back(k.T_world_body);
    run.checks.insert(run.checks.end(), k.gnss_checks.begin(), k.gnss_checks.end());
  }
  run.warnings = window.warnings();
  run.factors = window.sensor_factors();
  run.georef = window.georeference();
  return run;
}

GeoRun RunWgio(
    const std::filesystem::path& folder,
    const std::function<bool(GnssFix&)>& edit_fix = [](GnssFix&) { return true; },
    const std::function<void(InertialOdometryConfig&)>& edit_config = {}) {
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  InertialOdometryConfig config;
  config.max_solver_time_s = 10;  // only the iteration budget: the results do not depend on the load
  config.T_body_wheel = *FindStream(description, SensorKind::kWheel)->T_body_sensor;
  config.use_gnss = true;
  config.T_body_gnss = *FindStream(description, SensorKind::kGnss)->T_body_sensor;
  if (edit_config) edit_config(config);
  auto wgio = InertialOdometry::Create(config);
  EXPECT_TRUE(wgio.ok()) << wgio.error();
  return Run(*wgio, **reader, edit_fix);
}

GeoRun RunLwgio(
    const std::filesystem::path& folder,
    const std::function<bool(GnssFix&)>& edit_fix = [](GnssFix&) { return true; }) {
  auto reader = OpenDataset(folder.string());
  EXPECT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  LidarOdometryConfig config;
  config.use_imu = config.use_wheel = config.use_gnss = true;
  config.T_body_lidar = *FindStream(description, SensorKind::kLidar)->T_body_sensor;
  config.T_body_wheel = *FindStream(description, SensorKind::kWheel)->T_body_sensor;
  config.T_body_gnss = *FindStream(description, SensorKind::kGnss)->T_body_sensor;
  config.input_voxel_m = 0.5;
  config.max_solver_time_s = 10;
  auto lwgio = LidarOdometry::Create(config);
  EXPECT_TRUE(lwgio.ok()) << lwgio.error();
  return Run(*lwgio, **reader, edit_fix);
}

struct EnuError {
  double horizontal_rmse = 0, vertical_rmse = 0, max_horizontal = 0;
  int poses = 0;
};

// The estimate in the estimator's ENU frame (T_enu_world p) against the truth moved from the simulator's ENU
// frame into it through WGS84, without any alignment; poses after `from_s` of the sequence.
EnuError ErrorInEnu(const GeoRun& run, const std::filesystem::path& folder, double from_s) {
  auto truth = ReadTrajectory((folder / "groundtruth.tum").string());
  EXPECT_TRUE(truth.ok());
  auto truth_frame = EnuFrame::Create(kSimOrigin);
  auto run_frame = EnuFrame::Create(run.georef->origin);
  EXPECT_TRUE(truth_frame.ok() && run_frame.ok());
  EnuError error;
  double horizontal = 0, vertical = 0;
  for (std::size_t k = 0; k < run.estimate.size(); ++k) {
    const Stamp t = run.estimate.stamps[k];
    const std::optional<SE3> true_pose = truth->PoseAt(t);
    if (!true_pose || ToSeconds(t - truth->stamps.front()) < from_s) continue;
    const Eigen::Vector3d truth_enu =
        run_frame->EnuFromGeodetic(truth_frame->GeodeticFromEnu(true_pose->translation()));
    const Eigen::Vector3d e = run.georef->T_enu_world * run.estimate.poses[k].translation() - truth_enu;
    horizontal += e.head<2>().squaredNorm();
    vertical += e.z() * e.z();
    error.max_horizontal = std::max(error.max_horizontal, e.head<2>().norm());
    ++error.poses;
  }
  error.horizontal_rmse = std::sqrt(horizontal / std::max(error.poses, 1));
  error.vertical_rmse = std::sqrt(vertical / std::max(error.poses, 1));
  return error;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

int Count(const std::vector<std::string>& lines, const std::string& part) {
  return static_cast<int>(std::count_if(
      lines.begin(), lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; }));
}

// An edit_fix that moves the fixes in [from_s, to_s) after the first fix's stamp (set in *first) north_m
// north (multipath), counting them in *moved.
std::function<bool(GnssFix&)> Multipath(double from_s, double to_s, double north_m, Stamp* first,
                                        int* moved) {
  *first = 0;
  *moved = 0;
  return [=](GnssFix& fix) {
    if (*first == 0) *first = fix.stamp;
    const double t = ToSeconds(fix.stamp - *first);
    if (t >= from_s && t < to_s) {
      fix.latitude_deg += north_m / 111'200.0;
      ++*moved;
    }
    return true;
  };
}

TEST(GnssInWindow, WgioWithRtkFixesFollowsTheTruthInEnuWithoutAlignment) {
  uf::testing::TempDir dir;
  const auto folder = Simulate(dir, 25.0, sim::GnssQuality::kRtkFixed, /*lidar=*/false);
  const GeoRun run = RunWgio(folder);
  ASSERT_TRUE(run.georef) << run.factors.gnss_alignment << "\n" << Joined(run.warnings);
  EXPECT_GT(run.factors.gnss.added, 80) << run.factors.gnss_alignment;
  EXPECT_EQ(run.factors.gnss.rejected, 0) << Joined(run.warnings);
  // After the alignment has started (10 m of driving, ~5 s): the RTK fixes (2 cm horizontal, 4 cm vertical,
  // 2 s correlation) hold the trajectory in ENU; the bound for WGIO with RTK is 0.05 m.
  const EnuError error = ErrorInEnu(run, folder, 6.0);
  EXPECT_GT(error.poses, 150);
  EXPECT_LT(error.horizontal_rmse, 0.05) << "max " << error.max_horizontal;
  EXPECT_LT(error.vertical_rmse, 0.1);
  // Every fix placed after the alignment's start was tested before its factor (the pairs of the start too);
  // with RTK fixes the prediction is centimetres from them.
  const SensorFactorStats::Innovations& innovations = run.factors.gnss_innovations;
  EXPECT_EQ(innovations.tested, run.factors.gnss.added + run.factors.gnss.rejected);
  EXPECT_LT(innovations.horizontal_median_m, 0.05);
  EXPECT_LE(innovations.horizontal_median_m, innovations.horizontal_p95_m);
}

TEST(GnssInWindow, WgioWithSingleFixesStaysWithinTheirAccuracy) {
  uf::testing::TempDir dir;
  const auto folder = Simulate(dir, 25.0, sim::GnssQuality::kSingle, /*lidar=*/false);
  // Single fixes: 1.5 m horizontal, 3 m vertical, wandering with a 30 s correlation time; the bound
  // for the ENU position error is 1.5 m. Each fix independent (the default), and with the receiver's offset
  // among the window's states (factors/gnss_offset_factor.h), whose blocks leave with their nodes.
  for (double share : {0.0, 0.9}) {
    const GeoRun run = RunWgio(
        folder, [](GnssFix&) { return true; },
        [&](InertialOdometryConfig& c) { c.gnss.fix.offset_share = share; });
    ASSERT_TRUE(run.georef) << run.factors.gnss_alignment;
    EXPECT_GT(run.factors.gnss.added, 80) << share;
    const EnuError error = ErrorInEnu(run, folder, 6.0);
    EXPECT_GT(error.poses, 150);
    EXPECT_LT(error.horizontal_rmse, 1.5) << "offset share " << share;
    EXPECT_LT(error.vertical_rmse, 3.0) << "offset share " << share;
  }
}

TEST(GnssInWindow, IntegrityCheckRejectsMultipathJumpsInLwgio) {
  uf::testing::TempDir dir;
  const auto folder = Simulate(dir, 15.0, sim::GnssQuality::kRtkFixed, /*lidar=*/true);
  const GeoRun clean = RunLwgio(folder);
  ASSERT_TRUE(clean.georef) << clean.factors.gnss_alignment;
  // Every fix from 10 s to 11 s jumps 20 m north (a multipath reflection, well after the alignment
  // started): its innovation is ~20 m against a gate of a few cm + 1 m prediction sigma.
  int jumped = 0;
  Stamp first_stamp = 0;
  const GeoRun run = RunLwgio(folder, Multipath(10.0, 11.0, 20.0, &first_stamp, &jumped));
  ASSERT_TRUE(run.georef);
  EXPECT_EQ(jumped, 5);
  EXPECT_EQ(run.factors.gnss.rejected, jumped) << Joined(run.warnings);
  // The first jumped fix steps from the one before: the step guard holds it and the rest of the jump out
  // (one warning), until the fixes are back.
  EXPECT_EQ(run.factors.gnss_held_out, jumped) << Joined(run.warnings);
  EXPECT_EQ(Count(run.warnings, "held out by the step guard"), 1);
  // The keyframes carry each tested fix's reliability score: the jumped ones inactive with their innovation
  // term saturated (D >= 1/3 from it alone), the RTK fixes around them near 0 (quality 1, a covariance of
  // centimetres, an innovation within the gate).
  int inactive = 0;
  double worst_active = 0;
  for (const GnssCheck& check : run.checks) {
    EXPECT_EQ(check.fix_quality, 1.0);
    if (check.active) {
      worst_active = std::max(worst_active, check.score);
    } else {
      ++inactive;
      EXPECT_GE(check.score, 1.0 / 3.0 - 1e-12);
      const Stamp from = first_stamp + 10 * kNanosecondsPerSecond;
      EXPECT_TRUE(check.stamp >= from && check.stamp < from + kNanosecondsPerSecond) << check.stamp;
    }
  }
  EXPECT_EQ(inactive, jumped);
  EXPECT_GE(run.checks.size(), 30u);  // 5 Hz fixes from the alignment's start on
  EXPECT_LT(worst_active, 1.0 / 3.0);
  // The trajectory does not move: the same ENU error as without the jumps, to the millimetre.
  const EnuError a = ErrorInEnu(clean, folder, 6.0), b = ErrorInEnu(run, folder, 6.0);
  EXPECT_LT(b.horizontal_rmse, 0.05);
  EXPECT_NEAR(a.horizontal_rmse, b.horizontal_rmse, 0.005);
}

// The largest horizontal distance between two runs' positions in their ENU frames, at their common stamps.
double MaxHorizontalDisplacement(const GeoRun& a, const GeoRun& b) {
  double largest = 0;
  for (std::size_t i = 0, j = 0; i < a.estimate.size() && j < b.estimate.size();) {
    if (a.estimate.stamps[i] < b.estimate.stamps[j]) {
      ++i;
    } else if (b.estimate.stamps[j] < a.estimate.stamps[i]) {
      ++j;
    } else {
      const Eigen::Vector3d d = a.georef->T_enu_world * a.estimate.poses[i++].translation() -
                                b.georef->T_enu_world * b.estimate.poses[j++].translation();
      largest = std::max(largest, d.head<2>().norm());
    }
  }
  return largest;
}

// A lasting multipath (5 m north for 5 s, ~40 m of driving) in WGIO with RTK fixes. The innovation test
// alone admits it once its prediction uncertainty, growing with the distance since the last accepted fix,
// covers 5 m; the step guard holds the fixes out from the step until they are back (docs/METHOD.md
// "Factor-wise reliability scheduling", GNSS step guard). The bound: no multipath jump moves the
// trajectory by more than 0.2 m (measured: 0.071 m guarded, 6.05 m without the guard).
TEST(GnssInWindow, StepGuardKeepsALastingMultipathOut) {
  uf::testing::TempDir dir;
  const auto folder = Simulate(dir, 25.0, sim::GnssQuality::kRtkFixed, /*lidar=*/false);
  const GeoRun clean = RunWgio(folder);
  ASSERT_TRUE(clean.georef) << clean.factors.gnss_alignment;
  Stamp first_stamp = 0;
  int jumped = 0;
  const GeoRun guarded = RunWgio(folder, Multipath(12.0, 17.0, 5.0, &first_stamp, &jumped));
  const GeoRun alone = RunWgio(folder, Multipath(12.0, 17.0, 5.0, &first_stamp, &jumped),
                               [](InertialOdometryConfig& c) { c.gnss.step_max_hold_s = 0; });
  ASSERT_TRUE(guarded.georef && alone.georef);
  EXPECT_EQ(jumped, 25);
  const double moved_guarded = MaxHorizontalDisplacement(guarded, clean);
  const double moved_alone = MaxHorizontalDisplacement(alone, clean);
  ::testing::Test::RecordProperty("moved_guarded_m", std::to_string(moved_guarded));
  ::testing::Test::RecordProperty("moved_alone_m", std::to_string(moved_alone));
  EXPECT_EQ(guarded.factors.gnss_held_out, jumped) << Joined(guarded.warnings);
  EXPECT_EQ(alone.factors.gnss_held_out, 0);
  EXPECT_LT(moved_guarded, 0.2);
  EXPECT_GT(moved_alone, 1.0);
}

TEST(GnssInWindow, BadFixesAreCountedAndSkippedNeverANanPose) {
  uf::testing::TempDir dir;
  const auto folder = Simulate(dir, 20.0, sim::GnssQuality::kRtkFixed, /*lidar=*/false);
  int index = 0;
  const GeoRun run = RunWgio(folder, [&](GnssFix& fix) {
    switch (index++ % 10) {
      case 1:
        fix.status = GnssFixStatus::kNoFix;
        break;
      case 3:
        fix.latitude_deg = std::numeric_limits<double>::quiet_NaN();
        break;
      case 5:
        fix.covariance_enu.setZero();  // COVARIANCE_TYPE_UNKNOWN: rejected by default
        break;
      case 7:
        if (index > 60) fix.longitude_deg += 0.05;  // ~3.6 km east, once the alignment runs
        break;
      case 9:
        fix.stamp -= kNanosecondsPerSecond;  // before the previous fix
        break;
      default:
        break;
    }
    return true;
  });
  ASSERT_TRUE(run.georef) << run.factors.gnss_alignment << "\n" << Joined(run.warnings);
  EXPECT_EQ(Count(run.warnings, "skipped: no fix"), 10) << Joined(run.warnings);
  EXPECT_EQ(Count(run.warnings, "skipped: non-finite position"), 10) << Joined(run.warnings);
  EXPECT_EQ(Count(run.warnings, "skipped: all-zero covariance"), 10) << Joined(run.warnings);
  EXPECT_EQ(Count(run.warnings, "skipped: not after"), 10) << Joined(run.warnings);
  EXPECT_GE(run.factors.gnss.skipped, 40);
  EXPECT_GE(run.factors.gnss.rejected, 3);  // the kilometre jumps after the alignment started
  const EnuError error = ErrorInEnu(run, folder, 6.0);
  EXPECT_LT(error.horizontal_rmse, 0.1);
}

}  // namespace
}  // namespace uf::estimator
