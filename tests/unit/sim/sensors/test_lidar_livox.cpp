// Livox-like LiDAR: per-point times with rolling acquisition, field of view, point rate, and the
// non-repetitive pattern whose coverage grows with integration time.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <set>

#include "lidar_test_support.h"
#include "odometry/sim/sensors/lidar_model.h"

namespace uf::sim {
namespace {

using namespace uf::sim::test;

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(LidarLivox, PointsLieOnTheSceneWithThePoseAtTheirOwnTime) {
  const Scene scene = BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = BriskSpline();
  auto lidar = LidarSimulator::Create(ExactConfig("livox_avia"), caster, spline, MountTBodyLidar(), 9);
  ASSERT_TRUE(lidar.ok()) << lidar.error();
  EXPECT_FALSE(lidar->is_spinning());
  EXPECT_EQ(lidar->rings(), 6);
  const Stamp start = kTrajectoryBegin + 123'456'789;
  const LidarScan scan = lidar->Scan(start).value();
  // ~240 k points/s over 0.1 s; in the closed room every beam returns.
  EXPECT_NEAR(static_cast<double>(scan.points.size()), 24000.0, 5.0);
  double worst = 0.0;
  std::int32_t previous = -1;
  for (const LidarPoint& p : scan.points) {
    ASSERT_GE(p.offset_ns, 0);
    ASSERT_LT(p.offset_ns, 100'000'000);
    EXPECT_GT(p.offset_ns, previous);  // continuous per-point times, in acquisition order
    previous = p.offset_ns;
    EXPECT_LT(p.ring, 6);
    const SE3 T_world_lidar = spline.Evaluate(start + p.offset_ns).T_world_body * MountTBodyLidar();
    worst = std::max(worst, DistanceToMesh(scene.mesh, T_world_lidar * PointOf(p)));
  }
  EXPECT_LT(worst, 1e-4);
}

// Occupied 0.25 x 0.25 deg cells of (azimuth, elevation) of the beam directions of a static lidar's frames.
std::set<std::pair<int, int>> CellsAfter(const LidarSimulator& lidar, int frames) {
  std::set<std::pair<int, int>> cells;
  for (int f = 0; f < frames; ++f) {
    const LidarScan scan = lidar.Scan(kTrajectoryBegin + f * lidar.period()).value();
    for (const LidarPoint& p : scan.points) {
      const double azimuth = std::atan2(p.y, p.x) / kDeg;
      const double elevation = std::atan2(p.z, std::hypot(p.x, p.y)) / kDeg;
      cells.emplace(static_cast<int>(std::floor(azimuth * 4)), static_cast<int>(std::floor(elevation * 4)));
    }
  }
  return cells;
}

TEST(LidarLivox, ForwardFieldOfViewAndCoverageGrowingAcrossFrames) {
  Scene scene = BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = StaticSpline(Eigen::Vector3d(-15, 0, 1));  // looking +x down the room
  auto lidar = LidarSimulator::Create(ExactConfig("livox_avia"), caster, spline, SE3(), 9);
  ASSERT_TRUE(lidar.ok()) << lidar.error();

  const LidarScan scan = lidar->Scan(kTrajectoryBegin).value();
  double max_azimuth = 0.0, max_elevation = 0.0;
  for (const LidarPoint& p : scan.points) {
    const double azimuth = std::atan2(p.y, p.x) / kDeg;
    const double elevation = std::atan2(p.z, std::hypot(p.x, p.y)) / kDeg;
    max_azimuth = std::max(max_azimuth, std::abs(azimuth));
    max_elevation = std::max(max_elevation, std::abs(elevation));
  }
  EXPECT_LE(max_azimuth, 70.4 / 2 + 1e-3);
  EXPECT_GT(max_azimuth, 70.4 / 2 * 0.95);
  EXPECT_LE(max_elevation, 77.2 / 2 + 1e-3);
  EXPECT_GT(max_elevation, 77.2 / 2 * 0.95);

  // Non-repetitive: further frames light up cells no earlier frame did. The field of view (an ellipse in
  // these coordinates) holds about pi * 35.2 * 38.6 * 16 = 68300 cells; a frame of 24000 points leaves most
  // empty. A repeating pattern would stay at the one-frame count.
  const std::size_t one = CellsAfter(*lidar, 1).size();
  const std::size_t two = CellsAfter(*lidar, 2).size();
  const std::size_t ten = CellsAfter(*lidar, 10).size();
  std::cout << "livox coverage (0.25 deg cells): 1 frame " << one << ", 2 frames " << two << ", 10 frames "
            << ten << "\n";
  EXPECT_GT(two, one * 1.4);
  EXPECT_GT(ten, two * 1.4);
  EXPECT_LT(ten, 70000u);
}

TEST(LidarLivox, PatternPhaseContinuesAcrossFrames) {
  // Two consecutive 0.1 s frames are the same points as one 0.2 s frame (at 5 Hz) split in two.
  const Scene scene = BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = BriskSpline();
  LidarConfig config = ExactConfig("livox_avia");
  const LidarSimulator fast = std::move(LidarSimulator::Create(config, caster, spline, SE3(), 1).value());
  config.rate_hz = 5.0;
  const LidarSimulator slow = std::move(LidarSimulator::Create(config, caster, spline, SE3(), 1).value());
  const Stamp start = kTrajectoryBegin + 10'000'000;
  const LidarScan a = fast.Scan(start).value();
  const LidarScan b = fast.Scan(start + fast.period()).value();
  const LidarScan whole = slow.Scan(start).value();
  ASSERT_EQ(a.points.size() + b.points.size(), whole.points.size());
  for (std::size_t i = 0; i < whole.points.size(); ++i) {
    const bool first = i < a.points.size();
    const LidarPoint& part = first ? a.points[i] : b.points[i - a.points.size()];
    const Stamp part_time = (first ? a.stamp : b.stamp) + part.offset_ns;
    ASSERT_EQ(part_time, whole.stamp + whole.points[i].offset_ns) << i;
    ASSERT_EQ(part.x, whole.points[i].x) << i;
    ASSERT_EQ(part.ring, whole.points[i].ring) << i;
  }
}

TEST(LidarLivox, SameSeedGivesIdenticalFramesForAnyThreadCount) {
  const Scene scene = BoxRoomScene();
  const RayCaster caster = std::move(RayCaster::Create(scene).value());
  const TrajectorySpline spline = BriskSpline();
  LidarConfig config = ExactConfig("livox_avia");
  config.range_noise_std_m = 0.02;
  config.dropout_probability = 0.2;
  config.threads = 1;
  const LidarScan reference =
      LidarSimulator::Create(config, caster, spline, SE3(), 77).value().Scan(kTrajectoryBegin).value();
  for (const int threads : {2, 5}) {
    config.threads = threads;
    const LidarScan again =
        LidarSimulator::Create(config, caster, spline, SE3(), 77).value().Scan(kTrajectoryBegin).value();
    EXPECT_TRUE(Identical(reference, again)) << threads;
  }
}

}  // namespace
}  // namespace uf::sim
