// MapRaySurface (lidar/map_ray_depth.h) against hand-computed intersections: a ray meets a wall of points at
// the distance the geometry gives (within the plane's thickness), on the wall's plane, a nearer wall hides a
// farther one, a ray
// grazing a floor or into empty space meets nothing, and the range bounds hold.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/estimator/lidar/map_ray_depth.h"

namespace uf::estimator {
namespace {

// Points every 0.1 m on the square [-size, size]^2 of the plane through `center` spanned by u and v.
std::vector<Eigen::Vector3d> Square(const Eigen::Vector3d& center, const Eigen::Vector3d& u,
                                    const Eigen::Vector3d& v, double size) {
  std::vector<Eigen::Vector3d> points;
  for (double a = -size; a <= size + 1e-9; a += 0.1)
    for (double b = -size; b <= size + 1e-9; b += 0.1) points.push_back(center + a * u + b * v);
  return points;
}

// The distance to the surface MapRaySurface meets, or nullopt.
std::optional<double> Distance(const VoxelHashMap& map, const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction, double min_m, double max_m) {
  const std::optional<MapRayHit> hit = MapRaySurface(map, origin, direction, min_m, max_m);
  if (!hit) return std::nullopt;
  return hit->distance;
}

VoxelHashMap WallAndFloor() {
  VoxelHashMap map(VoxelMapConfig{.max_points_per_voxel = 1000});
  // A wall x = 20.13 (y, z in [-6, 6]) and a floor z = -1.8 reaching x = 30.
  map.Insert(Square({20.13, 0, 0}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 6));
  map.Insert(Square({15, 0, -1.8}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 15));
  return map;
}

TEST(MapRaySurface, MeetsAWallWhereTheGeometrySays) {
  const VoxelHashMap map = WallAndFloor();
  const Eigen::Vector3d origin(0.2, 0.4, 0.1);
  for (const Eigen::Vector3d& target : {Eigen::Vector3d(20.13, 0.4, 0.1), Eigen::Vector3d(20.13, 3.7, 2.2),
                                        Eigen::Vector3d(20.13, -4.1, -1.0)}) {
    const Eigen::Vector3d direction = (target - origin).normalized();
    const std::optional<MapRayHit> hit = MapRaySurface(map, origin, direction, 0.5, 150);
    ASSERT_TRUE(hit) << target.transpose();
    EXPECT_NEAR(hit->distance, (target - origin).norm(), 0.01) << target.transpose();
    // On the wall's plane (x = 20.13, normal +-x).
    EXPECT_GT(std::abs(hit->plane.normal.x()), 0.999) << hit->plane.normal.transpose();
    EXPECT_NEAR(hit->plane.point.x(), 20.13, 0.01);
    EXPECT_GT(hit->plane.sigma, 0);
  }
}

TEST(MapRaySurface, DownwardRayMeetsTheFloor) {
  const VoxelHashMap map = WallAndFloor();
  const Eigen::Vector3d origin(0, 0, 0);
  const Eigen::Vector3d target(9, 1, -1.8);
  const std::optional<double> distance = Distance(map, origin, target.normalized(), 0.5, 150);
  ASSERT_TRUE(distance);
  EXPECT_NEAR(*distance, target.norm(), 0.01);
}

TEST(MapRaySurface, TheNearerWallHidesTheFartherOne) {
  VoxelHashMap map = WallAndFloor();
  map.Insert(Square({8.04, 0, 0}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 2));
  const std::optional<double> distance =
      Distance(map, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.5, 150);
  ASSERT_TRUE(distance);
  EXPECT_NEAR(*distance, 8.04, 0.01);
}

TEST(MapRaySurface, GrazingEmptyAndOutOfRangeRaysMeetNothing) {
  const VoxelHashMap map = WallAndFloor();
  // 0.1 m above the floor, descending at 0.01: it would meet the floor 10 m on, at an incidence where 1 cm
  // of plane error moves the hit by 1 m; grazed, not met.
  EXPECT_FALSE(
      Distance(map, Eigen::Vector3d(0, 0, -1.7), Eigen::Vector3d(0.6, 0.8, -0.01).normalized(), 0.5, 150));
  EXPECT_FALSE(Distance(map, Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0), 0.5, 150));  // away
  EXPECT_FALSE(Distance(map, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.5, 15));    // too short
  EXPECT_FALSE(Distance(map, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 25, 150));    // behind
  EXPECT_FALSE(Distance(map, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::UnitX(), 0.5, 150));
}

}  // namespace
}  // namespace uf::estimator
