// VoxelHashMap's plane kernel (VoxelMapConfig::neighbour_weight: where a voxel's plane passes) against
// analytic geometry: on a sphere of 2 m radius (a rock, a crown) the planes lie inside the surface by the
// depths computed by hand, 9.4 cm through the 3x3x3 block's centroid and 5.2 cm through the kernel's; on a
// flat wall every kernel gives the wall exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "odometry/estimator/lidar/voxel_hash_map.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Points every 2 cm (in angle) on the cap of a sphere of radius 2 m facing the sensor at the origin.
std::vector<Eigen::Vector3d> SphereCap(const Eigen::Vector3d& centre, double radius) {
  std::vector<Eigen::Vector3d> points;
  const double step = 0.02 / radius;
  for (double polar = 0; polar < 1.2; polar += step) {
    const int around = std::max(1, static_cast<int>(2 * kPi * std::sin(polar) / step));
    for (int k = 0; k < around; ++k) {
      const double azimuth = 2 * kPi * k / around;
      // The cap's pole points from the centre towards the sensor (-x).
      const Eigen::Vector3d d(-std::cos(polar), std::sin(polar) * std::cos(azimuth),
                              std::sin(polar) * std::sin(azimuth));
      points.push_back(centre + radius * d);
    }
  }
  return points;
}

// Mean distance of the query points (on the sphere, near the cap's pole) from their voxel's plane. Near the
// pole a plane with the sphere's normal through the (weighted) centroid of the block's points lies inside
// the sphere by the mean of d^2 / (2 R) over them, d their offset across the pole from the query voxel's
// centre. Unweighted, d is
// uniform over the block's 1.5 m per axis: variance 1.5^2 / 12 per axis, depth 2 x 0.1875 / 4 = 0.094 m.
// With w = 0.25 per axis: the offsets 0 and +-0.5 m weighted 1 and w each, plus the 0.5 m voxel's own
// spread: 2 w 0.25 / (1 + 2 w) + 0.5^2 / 12 = 0.104 per axis, depth 2 x 0.104 / 4 = 0.052 m.
double MeanDistanceOfTheSurfaceFromItsPlanes(double neighbour_weight) {
  const Eigen::Vector3d centre(8.03, 0.11, 0.07);
  const double radius = 2.0;
  VoxelHashMap map(VoxelMapConfig{.max_points_per_voxel = 5000, .neighbour_weight = neighbour_weight});
  map.Insert(SphereCap(centre, radius));
  double sum = 0;
  int n = 0;
  for (double a = -0.3; a <= 0.3 + 1e-9; a += 0.1)
    for (double b = -0.3; b <= 0.3 + 1e-9; b += 0.1) {
      const Eigen::Vector3d direction = Eigen::Vector3d(-1, a, b).normalized();
      const Eigen::Vector3d q = centre + radius * direction;
      const auto plane = map.PlaneNear(q);
      if (!plane) {
        ADD_FAILURE() << "no plane at " << q.transpose() << " (weight " << neighbour_weight << ")";
        continue;
      }
      EXPECT_GT(std::abs(plane->normal.dot(direction)), std::cos(15 * kPi / 180));  // the sphere's normal
      sum += std::abs(plane->normal.dot(q - plane->point));
      ++n;
    }
  EXPECT_EQ(n, 49);
  return sum / std::max(n, 1);
}

TEST(VoxelHashMap, KernelBringsThePlaneOfACurvedSurfaceCloserToIt) {
  const double block = MeanDistanceOfTheSurfaceFromItsPlanes(1.0);
  const double kernel = MeanDistanceOfTheSurfaceFromItsPlanes(0.25);
  EXPECT_NEAR(block, 0.094, 0.02);  // (above)
  EXPECT_NEAR(kernel, 0.052, 0.015);
  EXPECT_LT(kernel, 0.6 * block);
}

// A flat wall (x = 5.13, points every 5 cm): any kernel gives the wall itself.
TEST(VoxelHashMap, KernelLeavesAFlatWallExact) {
  std::vector<Eigen::Vector3d> wall;
  for (double y = -3; y <= 3; y += 0.05)
    for (double z = -1; z <= 3; z += 0.05) wall.emplace_back(5.13, y, z);
  for (double weight : {1.0, 0.25, 0.05}) {
    VoxelHashMap map(VoxelMapConfig{.max_points_per_voxel = 1000, .neighbour_weight = weight});
    map.Insert(wall);
    for (const Eigen::Vector3d& q :
         {Eigen::Vector3d(5.13, 0.37, 1.21), Eigen::Vector3d(5.13, -2.01, -0.33)}) {
      const auto plane = map.PlaneNear(q);
      ASSERT_TRUE(plane) << "weight " << weight;
      EXPECT_GT(std::abs(plane->normal.x()), 1 - 1e-9) << "weight " << weight;
      EXPECT_NEAR(plane->point.x(), 5.13, 1e-9) << "weight " << weight;
    }
  }
}

TEST(VoxelHashMap, ValidatesItsNeighbourWeight) {
  EXPECT_TRUE(VoxelMapConfig{.neighbour_weight = 1.0}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.neighbour_weight = 0.0}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.neighbour_weight = 1.5}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.neighbour_weight = std::nan("")}.Validate().ok());
}

}  // namespace
}  // namespace uf::estimator
