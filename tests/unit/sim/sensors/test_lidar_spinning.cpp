// Spinning LiDAR simulation against independent truth: the scene geometry (brute-force point-to-mesh
// distance) with the true pose at each point's own time, the datasheet elevation tables, and the KITTI
// reader's azimuth-to-time convention.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "lidar_test_support.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "odometry/sim/sensors/lidar_model.h"

namespace uf::sim {
namespace {

using namespace uf::sim::test;

constexpr double kDeg = std::numbers::pi / 180.0;

struct World {
  Scene scene = BoxRoomScene();
  RayCaster caster = std::move(RayCaster::Create(scene).value());
  TrajectorySpline spline = BriskSpline();
};

LidarSimulator MakeSimulator(const World& world, const LidarConfig& config, std::uint64_t seed = 1) {
  auto simulator = LidarSimulator::Create(config, world.caster, world.spline, MountTBodyLidar(), seed);
  EXPECT_TRUE(simulator.ok()) << simulator.error();
  return std::move(simulator.value());
}

TEST(TrajectorySplinePose, MatchesEvaluate) {
  const TrajectorySpline spline = BriskSpline();
  for (Stamp t = spline.begin(); t <= spline.end(); t += 7'777'777) {
    const SE3 pose = spline.Pose(t);
    const SE3 truth = spline.Evaluate(t).T_world_body;
    EXPECT_LT((pose.matrix() - truth.matrix()).norm(), 1e-12) << t;
  }
}

TEST(LidarSpinning, NoiseFreePointsLieOnTheSceneWithThePoseAtTheirOwnTime) {
  const World world;
  const LidarSimulator lidar = MakeSimulator(world, ExactConfig());
  const Stamp start = kTrajectoryBegin + 200'000'000;
  auto scan = lidar.Scan(start);
  ASSERT_TRUE(scan.ok()) << scan.error();
  // The room is closed and everything is within 80 m: every one of the 900 x 32 beams returns.
  EXPECT_EQ(scan->points.size(), 900u * 32u);
  double worst = 0.0, start_pose_sum = 0.0;
  int start_pose_off_by_cm = 0;
  const SE3 T_world_lidar_start = world.spline.Evaluate(start).T_world_body * MountTBodyLidar();
  for (const LidarPoint& point : scan->points) {
    const SE3 T_world_lidar = world.spline.Evaluate(start + point.offset_ns).T_world_body * MountTBodyLidar();
    worst = std::max(worst, DistanceToMesh(world.scene.mesh, T_world_lidar * PointOf(point)));
    // The same point placed with the scan-start pose (what a rigid, non-rolling model would do).
    const double off = DistanceToMesh(world.scene.mesh, T_world_lidar_start * PointOf(point));
    start_pose_sum += off;
    start_pose_off_by_cm += off > 0.01;
  }
  EXPECT_LT(worst, 1e-4);
  const double mean_start_pose_error = start_pose_sum / scan->points.size();
  EXPECT_GT(mean_start_pose_error, 0.05) << "rolling acquisition should matter on this trajectory";
  EXPECT_GT(start_pose_off_by_cm, static_cast<int>(scan->points.size() / 2));
}

TEST(LidarSpinning, RangeNoiseIsGaussianAlongTheBeamWithTheConfiguredSigma) {
  const World world;
  LidarConfig config = ExactConfig();
  const LidarSimulator exact = MakeSimulator(world, config, 5);
  config.range_noise_std_m = 0.05;
  const LidarSimulator noisy = MakeSimulator(world, config, 5);
  const Stamp start = kTrajectoryBegin + 100'000'000;
  const LidarScan clean = exact.Scan(start).value();
  const LidarScan measured = noisy.Scan(start).value();
  ASSERT_EQ(clean.points.size(), measured.points.size());
  std::vector<double> residuals;
  for (std::size_t i = 0; i < clean.points.size(); ++i) {
    const Eigen::Vector3d p = PointOf(measured.points[i]);
    const Eigen::Vector3d q = PointOf(clean.points[i]);
    ASSERT_EQ(measured.points[i].offset_ns, clean.points[i].offset_ns);
    EXPECT_LT((p.normalized() - q.normalized()).norm(), 1e-5) << "the noisy point leaves the beam";
    residuals.push_back(p.norm() - q.norm());
  }
  const double n = static_cast<double>(residuals.size());
  const double mean = std::accumulate(residuals.begin(), residuals.end(), 0.0) / n;
  double variance = 0.0;
  for (const double r : residuals) variance += (r - mean) * (r - mean);
  const double std_dev = std::sqrt(variance / (n - 1));
  EXPECT_NEAR(std_dev, 0.05, 0.005);
  EXPECT_NEAR(mean, 0.0, 4 * 0.05 / std::sqrt(n));
  int beyond_two_sigma = 0;
  for (const double r : residuals) beyond_two_sigma += std::abs(r) > 0.1;
  EXPECT_NEAR(beyond_two_sigma / n, 0.0455, 0.006);  // Gaussian tails
}

TEST(LidarSpinning, PresetElevationTablesMatchTheDatasheets) {
  const auto vlp16 = SpinningPatternFor("spinning16");
  ASSERT_TRUE(vlp16.has_value());
  ASSERT_EQ(vlp16->elevations_rad.size(), 16u);
  for (int r = 0; r < 16; ++r) EXPECT_NEAR(vlp16->elevations_rad[r], (-15.0 + 2.0 * r) * kDeg, 1e-12);

  const auto hdl32 = SpinningPatternFor("spinning32");
  ASSERT_TRUE(hdl32.has_value());
  ASSERT_EQ(hdl32->elevations_rad.size(), 32u);
  EXPECT_NEAR(hdl32->elevations_rad.front(), -30.67 * kDeg, 1e-12);
  EXPECT_NEAR(hdl32->elevations_rad.back(), 10.67 * kDeg, 1e-12);
  for (int r = 1; r < 32; ++r) {
    EXPECT_NEAR(hdl32->elevations_rad[r] - hdl32->elevations_rad[r - 1], 1.3335 * kDeg, 0.001 * kDeg);
  }

  const auto hdl64 = SpinningPatternFor("spinning64");
  ASSERT_TRUE(hdl64.has_value());
  ASSERT_EQ(hdl64->elevations_rad.size(), 64u);
  EXPECT_NEAR(hdl64->elevations_rad.front(), -24.9 * kDeg, 1e-12);
  EXPECT_NEAR(hdl64->elevations_rad.back(), 2.0 * kDeg, 1e-12);

  const auto os128 = SpinningPatternFor("spinning128");
  ASSERT_TRUE(os128.has_value());
  ASSERT_EQ(os128->elevations_rad.size(), 128u);
  EXPECT_NEAR(os128->elevations_rad.front(), -22.5 * kDeg, 1e-12);
  EXPECT_NEAR(os128->elevations_rad.back(), 22.5 * kDeg, 1e-12);

  for (const auto* pattern : {&*vlp16, &*hdl32, &*hdl64, &*os128}) {  // ring 0 lowest, ascending
    EXPECT_TRUE(std::is_sorted(pattern->elevations_rad.begin(), pattern->elevations_rad.end()));
  }
  EXPECT_FALSE(SpinningPatternFor("livox_avia").has_value());
  EXPECT_FALSE(SpinningPatternFor("spinning48").has_value());
}

TEST(LidarSpinning, PointElevationsMatchThePresetByRing) {
  const World world;
  for (const char* model : {"spinning16", "spinning32", "spinning64", "spinning128"}) {
    LidarConfig config = ExactConfig(model);
    config.horizontal_resolution_deg = 2.0;
    const LidarSimulator lidar = MakeSimulator(world, config);
    const std::vector<double> table = SpinningPatternFor(model)->elevations_rad;
    const LidarScan scan = lidar.Scan(kTrajectoryBegin).value();
    EXPECT_EQ(scan.points.size(), 180 * table.size()) << model;
    for (const LidarPoint& p : scan.points) {
      ASSERT_LT(p.ring, table.size());
      const double elevation = std::atan2(p.z, std::hypot(p.x, p.y));
      EXPECT_NEAR(elevation, table[p.ring], 2e-6) << model << " ring " << p.ring;
    }
  }
}

TEST(LidarSpinning, OffsetsIncreaseWithColumnAndAgreeWithAzimuthDerivedTimes) {
  const World world;
  const LidarSimulator lidar = MakeSimulator(world, ExactConfig());
  const Stamp start = kTrajectoryBegin + 300'000'000;
  const LidarScan scan = lidar.Scan(start).value();
  EXPECT_EQ(scan.stamp, start);
  EXPECT_EQ(scan.end, start + 100'000'000);
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_TRUE(scan.has_ring);
  ASSERT_EQ(lidar.columns(), 900);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const LidarPoint& p = scan.points[i];
    ASSERT_GE(p.offset_ns, 0);
    ASSERT_LT(p.offset_ns, 100'000'000);
    // Acquisition order: column by column, beams of a column share its time, column c at c * period / 900.
    const std::size_t column = i / 32;
    EXPECT_EQ(p.offset_ns, static_cast<std::int64_t>(column) * 100'000'000 / 900);
    EXPECT_EQ(p.ring, i % 32);
  }
  // The first column points backwards (-x), the middle one forwards: clockwise seen from above.
  EXPECT_LT(scan.points.front().x, 0.0f);
  EXPECT_GT(scan.points[450 * 32].x, 0.0f);
  EXPECT_GT(scan.points[225 * 32].y, 0.0f);  // a quarter turn clockwise (from above) from -x is +y (left)
  EXPECT_LT(scan.points[675 * 32].y, 0.0f);  // three quarters: -y (right)
  // The reader's convention recovers each point's time from its azimuth alone.
  LidarScan derived = scan;
  DerivePointTimesFromAzimuth(derived, lidar.period());
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    EXPECT_NEAR(derived.points[i].offset_ns, scan.points[i].offset_ns, 100) << i;
  }
}

TEST(LidarSpinning, DropoutRemovesTheConfiguredFraction) {
  const World world;
  LidarConfig config = ExactConfig();
  const std::size_t all = MakeSimulator(world, config).Scan(kTrajectoryBegin).value().points.size();
  config.dropout_probability = 0.3;
  const std::size_t kept = MakeSimulator(world, config).Scan(kTrajectoryBegin).value().points.size();
  // Binomial: std of the kept fraction sqrt(0.21 / 28800) = 0.0027.
  EXPECT_NEAR(static_cast<double>(kept) / all, 0.7, 0.015);
  config.dropout_probability = 1.0;
  EXPECT_TRUE(MakeSimulator(world, config).Scan(kTrajectoryBegin).value().points.empty());
}

TEST(LidarSpinning, RangeLimitsAreHonoured) {
  const World world;
  LidarConfig config = ExactConfig();
  config.min_range_m = 4.0;
  config.max_range_m = 12.0;
  const LidarScan scan = MakeSimulator(world, config).Scan(kTrajectoryBegin).value();
  ASSERT_FALSE(scan.points.empty());
  EXPECT_LT(scan.points.size(), 900u * 32u);
  for (const LidarPoint& p : scan.points) {
    EXPECT_GE(PointOf(p).norm(), 4.0 - 1e-4);
    EXPECT_LE(PointOf(p).norm(), 12.0 + 1e-4);
  }
}

TEST(LidarSpinning, IntensityIsReflectivityTimesCosineOfIncidence) {
  // Static lidar 3 m in front of a lone wall at x = 5 (no other geometry): I = round(255 rho |d_x|).
  Scene scene;
  AddWallX(scene.mesh, 5.0f, -100, 100, -100, 100, Material::kRoadMarking);
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = StaticSpline(Eigen::Vector3d(2, 0, 0));
  LidarConfig config = ExactConfig("spinning16");
  auto lidar = LidarSimulator::Create(config, caster, spline, SE3(), 3);
  ASSERT_TRUE(lidar.ok()) << lidar.error();
  const LidarScan scan = lidar->Scan(kTrajectoryBegin).value();
  ASSERT_GT(scan.points.size(), 100u);
  const double rho = AppearanceOf(Material::kRoadMarking).reflectivity;
  for (const LidarPoint& p : scan.points) {
    EXPECT_NEAR(p.x, 3.0f, 1e-4f);
    const double cos_incidence = PointOf(p).normalized().x();
    EXPECT_NEAR(p.intensity, std::round(255.0 * rho * cos_incidence), 1.0);
  }
}

TEST(LidarSpinning, SameSeedGivesIdenticalScansForAnyThreadCount) {
  const World world;
  LidarConfig config = ExactConfig();
  config.range_noise_std_m = 0.03;
  config.dropout_probability = 0.1;
  config.threads = 1;
  const LidarScan reference = MakeSimulator(world, config, 42).Scan(kTrajectoryBegin + 50'000'000).value();
  for (const int threads : {2, 3, 7, 0}) {
    config.threads = threads;
    const LidarScan again = MakeSimulator(world, config, 42).Scan(kTrajectoryBegin + 50'000'000).value();
    EXPECT_TRUE(Identical(reference, again)) << threads << " threads";
  }
  const LidarScan other_seed = MakeSimulator(world, config, 43).Scan(kTrajectoryBegin + 50'000'000).value();
  EXPECT_FALSE(Identical(reference, other_seed));
  const LidarScan other_start = MakeSimulator(world, config, 42).Scan(kTrajectoryBegin + 150'000'000).value();
  EXPECT_FALSE(Identical(reference, other_start));
}

TEST(LidarSpinning, ScanOutsideTheTrajectoryIsAnError) {
  const World world;
  const LidarSimulator lidar = MakeSimulator(world, ExactConfig());
  auto before = lidar.Scan(kTrajectoryBegin - 1);
  ASSERT_FALSE(before.ok());
  EXPECT_NE(before.error().find("outside the trajectory"), std::string::npos) << before.error();
  EXPECT_FALSE(lidar.Scan(world.spline.end() - 50'000'000).ok());  // the sweep would end past the spline
  EXPECT_TRUE(lidar.Scan(world.spline.end() - 100'000'000).ok());
}

}  // namespace
}  // namespace uf::sim
