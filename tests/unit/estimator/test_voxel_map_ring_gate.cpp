// VoxelHashMap's ring gate (min_plane_rings) against analytic geometry: a single scan line across a tree
// trunk gives a plane only without the gate, the auto setting turns the gate on once a ring index of 31 or
// more shows, and two lines on a facade give the facade with the gate.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "odometry/estimator/lidar/voxel_hash_map.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A horizontal ring (elevation 0, sensor at the origin) across a vertical trunk of radius 0.5 m at 50 m: the
// points lie on an arc in the plane z = 0, with 0.2 m of depth, so the PCA sees a plane (lambda_min = 0) with
// normal z: the beam's cone, not the trunk, whose normal is horizontal everywhere. A point of the trunk 0.3 m
// above the line, on the surface, is then 0.3 m from that plane. With min_plane_rings = 2 the block has no
// plane; without ring information the gate does not apply.
TEST(VoxelHashMap, SingleScanLineAcrossATrunkGivesAPlaneOnlyWithoutTheRingGate) {
  const Eigen::Vector3d axis(50, 0.1, 0);  // the trunk's axis, vertical
  const double radius = 0.5;
  std::vector<Eigen::Vector3d> line;
  for (double azimuth = -0.6; azimuth <= 0.6; azimuth += 0.05) {  // deg, 0.04 m apart at 50 m
    const Eigen::Vector3d ray(std::cos(azimuth * kPi / 180), std::sin(azimuth * kPi / 180), 0);
    // Nearest hit of the ray with the cylinder (x - a)^2 + (y - b)^2 = r^2.
    const double b = ray.dot(axis), c = axis.squaredNorm() - radius * radius;
    if (b * b - c < 0) continue;
    line.push_back((b - std::sqrt(b * b - c)) * ray);
  }
  ASSERT_GE(line.size(), 10u);
  const std::vector<int> rings(line.size(), 15);
  const Eigen::Vector3d on_trunk = line[line.size() / 2] + Eigen::Vector3d(0, 0, 0.3);

  VoxelHashMap ungated(VoxelMapConfig{.min_plane_rings = 1});
  ungated.Insert(line, rings);
  const auto fake = ungated.PlaneNear(on_trunk);
  ASSERT_TRUE(fake);
  EXPECT_NEAR(std::abs(fake->normal.z()), 1.0, 1e-9);
  EXPECT_NEAR(std::abs(fake->normal.dot(on_trunk - fake->point)), 0.3, 1e-9);

  VoxelHashMap gated(VoxelMapConfig{.min_plane_rings = 2});
  gated.Insert(line, rings);
  EXPECT_FALSE(gated.PlaneNear(on_trunk));
  EXPECT_FALSE(gated.PlaneNear(line.front()));

  VoxelHashMap unknown_rings(VoxelMapConfig{.min_plane_rings = 2});
  unknown_rings.Insert(line);
  EXPECT_TRUE(unknown_rings.PlaneNear(on_trunk));
}

// min_plane_rings 0 (auto, the default) gates once the LiDAR shows a ring index of 31 or more (32 rings or
// more): a single scan line of ring 15 (a shallow arc on a facade) keeps its plane while the map has seen
// rings 0-30 only (a 16- or 31-ring LiDAR), and loses it once a point of ring 31 arrives anywhere in the map.
TEST(VoxelHashMap, AutoRingGateTurnsOnForALidarOf32RingsOrMore) {
  std::vector<Eigen::Vector3d> line;
  for (double y = -0.7; y <= 0.7; y += 0.05) line.emplace_back(50, y, 0.01 * y * y);  // a shallow arc
  const Eigen::Vector3d on_line = line[line.size() / 2];
  VoxelHashMap map;
  ASSERT_EQ(map.config().min_plane_rings, 0);
  map.Insert(line, std::vector<int>(line.size(), 15));
  map.Insert({Eigen::Vector3d(-20, 0, 0)}, {30});
  EXPECT_EQ(map.min_plane_rings_in_use(), 1);
  EXPECT_TRUE(map.PlaneNear(on_line));
  map.Insert({Eigen::Vector3d(-20, 5, 0)}, {31});
  EXPECT_EQ(map.min_plane_rings_in_use(), 2);
  EXPECT_FALSE(map.PlaneNear(on_line));
  map.Clear();  // the LiDAR stays the same
  EXPECT_EQ(map.min_plane_rings_in_use(), 2);
  EXPECT_EQ(VoxelHashMap(VoxelMapConfig{.min_plane_rings = 3}).min_plane_rings_in_use(), 3);
}

// Two rings on a flat facade x = 50: each ring alone is a straight line (no plane), the two together span
// the facade, and the gated map returns its plane: normal x, through x = 50.
TEST(VoxelHashMap, TwoScanLinesOnAFacadeGiveTheFacadeWithTheRingGate) {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> rings;
  for (const auto& [ring, elevation_deg] : {std::pair{15, 0.0}, std::pair{16, 0.5}})
    for (double y = -0.7; y <= 0.7; y += 0.05) {
      points.emplace_back(50, y, 50 * std::tan(elevation_deg * kPi / 180));
      rings.push_back(ring);
    }
  VoxelHashMap map(VoxelMapConfig{.min_plane_rings = 2});
  const Eigen::Vector3d query(50, 0.1, 0.2);
  map.Insert({points.begin(), points.begin() + points.size() / 2},
             {rings.begin(), rings.begin() + rings.size() / 2});
  EXPECT_FALSE(map.PlaneNear(query));  // one ring: one ring and a straight line
  map.Insert({points.begin() + points.size() / 2, points.end()},
             {rings.begin() + rings.size() / 2, rings.end()});
  const auto plane = map.PlaneNear(query);
  ASSERT_TRUE(plane);
  EXPECT_NEAR(std::abs(plane->normal.x()), 1.0, 1e-9);
  EXPECT_NEAR(plane->point.x(), 50.0, 1e-9);
}

}  // namespace
}  // namespace uf::estimator
