// VoxelDownsample against a constructed cloud whose voxel occupancy is known by construction: one point per
// voxel (the first seen), exact counts, whole LidarPoints kept (offset_ns, ring, intensity), floor (not
// truncation) at negative coordinates, non-finite points dropped; and the estimator's downsampling of
// prepared points: one of each voxel's own points, drawn alike whatever the acquisition order, also through
// nested voxels (map voxels inside registration voxels).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "odometry/estimator/lidar/voxel_downsample.h"
#include "odometry/estimator/lidar/voxel_key.h"
#include "odometry/estimator/lidar_odometry/scan_preparation.h"

namespace uf::estimator {
namespace {

LidarPoint Point(double x, double y, double z, std::int32_t offset_ns) {
  LidarPoint p;
  p.x = static_cast<float>(x);
  p.y = static_cast<float>(y);
  p.z = static_cast<float>(z);
  p.offset_ns = offset_ns;
  p.ring = static_cast<std::uint16_t>(offset_ns % 64);
  p.intensity = static_cast<float>(offset_ns) * 0.5f;
  return p;
}

TEST(VoxelDownsample, KeepsTheFirstPointOfEachVoxel) {
  // 5 x 4 x 3 voxels of 0.5 m (indices -2..2, -2..1, -1..1), each hit by 3 points at different places
  // inside it (0.1, 0.25, 0.4 of the edge), interleaved so that the first of each voxel comes first.
  const double voxel = 0.5;
  std::vector<LidarPoint> cloud;
  std::vector<LidarPoint> expected;
  std::int32_t offset = 0;
  for (double fraction : {0.1, 0.25, 0.4}) {
    for (int i = -2; i <= 2; ++i)
      for (int j = -2; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) {
          cloud.push_back(
              Point((i + fraction) * voxel, (j + fraction) * voxel, (k + fraction) * voxel, offset));
          if (fraction == 0.1) expected.push_back(cloud.back());
          offset += 1000;
        }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  cloud.push_back(Point(nan, 0, 0, 7));
  cloud.push_back(Point(0, std::numeric_limits<double>::infinity(), 0, 8));

  const std::vector<LidarPoint> kept = VoxelDownsample(cloud, voxel);
  ASSERT_EQ(kept.size(), 5u * 4u * 3u);
  for (std::size_t n = 0; n < kept.size(); ++n) {
    EXPECT_EQ(kept[n].x, expected[n].x);
    EXPECT_EQ(kept[n].y, expected[n].y);
    EXPECT_EQ(kept[n].z, expected[n].z);
    EXPECT_EQ(kept[n].offset_ns, expected[n].offset_ns);
    EXPECT_EQ(kept[n].ring, expected[n].ring);
    EXPECT_EQ(kept[n].intensity, expected[n].intensity);
  }
}

TEST(VoxelDownsample, SplitsAtZeroByFloor) {
  // -0.1 and 0.1 are in voxels -1 and 0 (truncation would merge them); 0.1 and 0.4 share voxel 0.
  const std::vector<LidarPoint> cloud = {Point(-0.1, 0, 0, 1), Point(0.1, 0, 0, 2), Point(0.4, 0, 0, 3),
                                         Point(-0.4, 0, 0, 4), Point(0.6, 0, 0, 5)};
  const std::vector<LidarPoint> kept = VoxelDownsample(cloud, 0.5);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[0].offset_ns, 1);
  EXPECT_EQ(kept[1].offset_ns, 2);
  EXPECT_EQ(kept[2].offset_ns, 5);
}

TEST(VoxelDownsample, EmptyAndDenseClouds) {
  EXPECT_TRUE(VoxelDownsample({}, 1.0).empty());
  // 10000 points inside one 1 m voxel: one survives, the first.
  std::vector<LidarPoint> cloud;
  for (int n = 0; n < 10000; ++n) cloud.push_back(Point(3.01 + 0.00009 * n, 4.5, -7.5, n));
  const std::vector<LidarPoint> kept = VoxelDownsample(cloud, 1.0);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].offset_ns, 0);
}

// A lattice of prepared points, 0.05 m apart, shuffled so that voxel borders are hit exactly and the
// acquisition order (alpha) is unrelated to the position.
std::vector<PreparedPoint> ShuffledLattice() {
  std::vector<PreparedPoint> points;
  for (int i = -60; i < 60; ++i)
    for (int j = -60; j < 60; j += 3)
      for (int k = -20; k < 20; k += 7)
        points.push_back({Eigen::Vector3d(0.05 * i, 0.05 * j, 0.05 * k), 0, 0});
  std::shuffle(points.begin(), points.end(), std::mt19937_64(9));
  for (std::size_t i = 0; i < points.size(); ++i) points[i].alpha = static_cast<double>(i) / points.size();
  return points;
}

VoxelIndex VoxelOfPoint(const PreparedPoint& p, double voxel_m) {
  return VoxelOf(p.point_lidar, 1.0 / voxel_m);
}

// One point per occupied voxel, each one of that voxel's own points, in order of the voxels' first
// appearance; and the same points again for the same scan.
TEST(DownsamplePrepared, KeepsOneOfEachVoxelsOwnPoints) {
  const std::vector<PreparedPoint> points = ShuffledLattice();
  const std::vector<PreparedPoint> kept = DownsamplePrepared(points, 1.0);
  ASSERT_EQ(kept.size(), 6u * 6u * 2u);  // x, y in [-3, 3), z in [-1, 0.75]: 1 m voxels
  std::vector<std::uint64_t> order;      // voxels by first appearance in the input
  for (const PreparedPoint& p : points) {
    const std::uint64_t key = PackVoxelKey(VoxelOfPoint(p, 1.0));
    if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
  }
  for (std::size_t v = 0; v < kept.size(); ++v) {
    EXPECT_EQ(PackVoxelKey(VoxelOfPoint(kept[v], 1.0)), order[v]) << v;
    const bool own = std::any_of(points.begin(), points.end(), [&](const PreparedPoint& p) {
      return p.point_lidar == kept[v].point_lidar && p.alpha == kept[v].alpha;
    });
    EXPECT_TRUE(own) << v;
  }
  const std::vector<PreparedPoint> again = DownsamplePrepared(points, 1.0);
  ASSERT_EQ(again.size(), kept.size());
  for (std::size_t v = 0; v < kept.size(); ++v) EXPECT_EQ(again[v].alpha, kept[v].alpha) << v;
}

// The kept point is drawn alike among a voxel's points, whatever their order: 4000 voxels of 8 points each,
// acquired in order along x, keep their n-th point 500 times each on average (binomial sd 21; the first
// point, as a first-point rule would keep, is no likelier than the last).
TEST(DownsamplePrepared, DrawsEveryPointOfAVoxelAlike) {
  std::vector<PreparedPoint> points;
  for (int v = 0; v < 4000; ++v)
    for (int n = 0; n < 8; ++n) points.push_back({Eigen::Vector3d(v + 0.1 * n + 0.05, 0.5, 0.5), n / 8.0, 0});
  const std::vector<PreparedPoint> kept = DownsamplePrepared(points, 1.0);
  ASSERT_EQ(kept.size(), 4000u);
  std::array<int, 8> times{};
  for (const PreparedPoint& p : kept) ++times[static_cast<int>(std::lround(p.alpha * 8))];
  for (int n = 0; n < 8; ++n) EXPECT_NEAR(times[n], 500, 5 * 21) << "point " << n << " of each voxel";
}

// LO downsamples a scan for the map (0.5 m) and, from those points, for registration (1.0 m): nested grids
// give one point per occupied registration voxel as a single pass does, each one of the voxel's own points.
TEST(DownsamplePrepared, NestedVoxelsKeepOnePointPerRegistrationVoxel) {
  const std::vector<PreparedPoint> points = ShuffledLattice();
  const std::vector<PreparedPoint> direct = DownsamplePrepared(points, 1.0);
  const std::vector<PreparedPoint> nested = DownsamplePrepared(DownsamplePrepared(points, 0.5), 1.0);
  ASSERT_EQ(nested.size(), direct.size());
  std::vector<std::uint64_t> keys;
  for (const PreparedPoint& p : nested) keys.push_back(PackVoxelKey(VoxelOfPoint(p, 1.0)));
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(std::unique(keys.begin(), keys.end()), keys.end());
}

}  // namespace
}  // namespace uf::estimator
