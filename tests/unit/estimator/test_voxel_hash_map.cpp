// VoxelHashMap against analytic geometry: the walls of a synthetic box room come back as planes (normal and
// offset of the true wall), its edges and corners fail the eigen-ratio gate, voxels hold at most
// max_points_per_voxel points, RemoveFarFrom drops exactly the voxels a brute force says are far, the plane
// planes follow inserts, shifted moment sums equal the moments of the points, a coarsened map equals the map
// of all points in wider voxels; and on a recorded KITTI scan most ground points get a plane with normal ~ z.
// The ring gate's tests are in test_voxel_map_ring_gate.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "odometry/estimator/lidar/voxel_downsample.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/so3.h"
#include "tests/support/temp_dir.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A box room [0, 10] x [0, 8] x [0, 4] (room frame) with points every 0.1 m on its six faces, placed in the
// world by T_world_room (a yaw, a small tilt and an offset that is not a multiple of the voxel size).
struct BoxRoom {
  Eigen::Vector3d size{10, 8, 4};
  SE3 T_world_room{SO3::Exp(Eigen::Vector3d(0.03, -0.02, 0.35)), Eigen::Vector3d(-3.13, 2.71, -1.07)};

  std::vector<Eigen::Vector3d> Points(double step = 0.1) const {
    std::vector<Eigen::Vector3d> points;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (double side : {0.0, size[axis]})
        for (double a = 0; a <= size[u] + 1e-9; a += step)
          for (double b = 0; b <= size[v] + 1e-9; b += step) {
            Eigen::Vector3d p;
            p[axis] = side;
            p[u] = a;
            p[v] = b;
            points.push_back(T_world_room * p);
          }
    }
    return points;
  }
};

TEST(VoxelHashMap, RecoversTheWallsOfABoxRoom) {
  const BoxRoom room;
  VoxelHashMap map(VoxelMapConfig{.max_points_per_voxel = 1000});
  map.Insert(room.Points());
  const Eigen::Matrix3d R = room.T_world_room.rotation();
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  int checked = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double side : {0.0, room.size[axis]})
      for (int n = 0; n < 20; ++n) {
        // A point of the face at least 1.8 m from the other faces: the 3x3x3 block sees this face only.
        Eigen::Vector3d p_room;
        p_room[axis] = side;
        p_room[u] = 1.8 + unit(random) * (room.size[u] - 3.6);
        p_room[v] = 1.8 + unit(random) * (room.size[v] - 3.6);
        const Eigen::Vector3d p = room.T_world_room * p_room;
        const auto plane = map.PlaneNear(p);
        ASSERT_TRUE(plane) << "axis " << axis << " side " << side;
        const Eigen::Vector3d true_normal = R.col(axis);
        const double angle = std::acos(std::min(1.0, std::abs(plane->normal.dot(true_normal))));
        EXPECT_LT(angle, 0.1 * kPi / 180) << "axis " << axis;
        EXPECT_NEAR(true_normal.dot(plane->point - p), 0.0, 1e-6);       // the plane point lies on the wall
        EXPECT_DOUBLE_EQ(plane->sigma, map.config().min_plane_sigma_m);  // a perfect plane: the floor
        ++checked;
      }
  }
  EXPECT_EQ(checked, 120);
}

TEST(VoxelHashMap, RejectsEdgesAndCornersByTheEigenRatioGate) {
  const BoxRoom room;
  VoxelHashMap map(VoxelMapConfig{.max_points_per_voxel = 1000});
  map.Insert(room.Points());
  int rejected = 0, total = 0;
  // Points along the 12 edges (two coordinates at a face, one free), corners included.
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double su : {0.0, room.size[u]})
      for (double sv : {0.0, room.size[v]})
        for (double a = 0; a <= room.size[axis] + 1e-9; a += 0.37) {
          Eigen::Vector3d p_room;
          p_room[axis] = a;
          p_room[u] = su;
          p_room[v] = sv;
          ++total;
          if (!map.PlaneNear(room.T_world_room * p_room)) ++rejected;
        }
  }
  EXPECT_EQ(rejected, total);
  EXPECT_GT(total, 100);
}

TEST(VoxelHashMap, KeepsAtMostMaxPointsPerVoxel) {
  VoxelHashMap map(VoxelMapConfig{.voxel_m = 1.0, .max_points_per_voxel = 20});
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 100; ++n) points.emplace_back(0.5 + 0.004 * n, 0.5, 0.5);  // voxel (0, 0, 0)
  for (int n = 0; n < 7; ++n) points.emplace_back(-0.5, 0.5 + 0.01 * n, 0.5);    // voxel (-1, 0, 0)
  map.Insert(points);
  EXPECT_EQ(map.voxel_count(), 2u);
  EXPECT_EQ(map.point_count(), 27u);
  map.Insert(points);  // the full voxel takes nothing more, the other fills up to 20
  EXPECT_EQ(map.point_count(), 34u);
  // The kept points of the full voxel are the first 20 inserted.
  int first_voxel = 0;
  for (const Eigen::Vector3d& p : map.Points())
    if (p.x() > 0) {
      EXPECT_LT(p.x(), 0.5 + 0.004 * 19 + 1e-6);
      ++first_voxel;
    }
  EXPECT_EQ(first_voxel, 20);
  map.Clear();
  EXPECT_EQ(map.voxel_count(), 0u);
  EXPECT_EQ(map.point_count(), 0u);
}

// Coarsened(4) against a map built from the same points with voxels 4 times larger and no cap on the points
// per voxel: the same voxels and, at every query (on the walls, inside the room, in empty voxels, at negative
// coordinates), the same plane or none; the coarsened map keeps no points of its own.
TEST(VoxelHashMap, CoarsenedEqualsTheMapOfAllPointsInWiderVoxels) {
  const BoxRoom room;
  const std::vector<Eigen::Vector3d> points = room.Points();
  VoxelHashMap fine(VoxelMapConfig{.voxel_m = 0.5, .max_points_per_voxel = 1000});
  fine.Insert(points);
  const VoxelMapConfig coarse_config{.voxel_m = 2.0, .max_points_per_voxel = 1'000'000};
  VoxelHashMap direct(coarse_config);
  direct.Insert(points);
  const VoxelHashMap coarse = fine.Coarsened(4, coarse_config);
  EXPECT_EQ(coarse.voxel_count(), direct.voxel_count());
  EXPECT_EQ(coarse.point_count(), 0u);
  EXPECT_TRUE(coarse.Points().empty());
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> box(-8, 12);
  int planes = 0;
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Vector3d p =
        n % 2 ? points[random() % points.size()] : Eigen::Vector3d(box(random), box(random), box(random));
    const auto expected = direct.PlaneNear(p), got = coarse.PlaneNear(p);
    ASSERT_EQ(got.has_value(), expected.has_value()) << p.transpose();
    if (!expected) continue;
    EXPECT_NEAR(std::abs(got->normal.dot(expected->normal)), 1.0, 1e-9) << p.transpose();
    EXPECT_LT((got->point - expected->point).norm(), 1e-9) << p.transpose();
    EXPECT_NEAR(got->sigma, expected->sigma, 1e-9) << p.transpose();
    ++planes;
  }
  EXPECT_GT(planes, 100);  // 6 m blocks in a 10 x 8 x 4 m room: most see two faces and fail the gate
}

TEST(VoxelHashMap, RemoveFarFromDropsExactlyTheFarVoxels) {
  const VoxelMapConfig config{.voxel_m = 0.5, .max_points_per_voxel = 3, .max_range_m = 12};
  VoxelHashMap map(config);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-20, 20);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 40000; ++n)
    points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  map.Insert(points);
  const Eigen::Vector3d center(1.3, -2.2, 0.4);
  map.RemoveFarFrom(center);
  // Brute force: points per voxel (capped), kept when the voxel centre is within range.
  std::map<std::tuple<int, int, int>, int> per_voxel;
  for (const Eigen::Vector3d& p : points) {
    const auto key =
        std::make_tuple(static_cast<int>(std::floor(p.x() / 0.5)), static_cast<int>(std::floor(p.y() / 0.5)),
                        static_cast<int>(std::floor(p.z() / 0.5)));
    per_voxel[key] = std::min(per_voxel[key] + 1, 3);
  }
  std::size_t voxels = 0, kept_points = 0;
  for (const auto& [key, count] : per_voxel) {
    const Eigen::Vector3d centre((std::get<0>(key) + 0.5) * 0.5, (std::get<1>(key) + 0.5) * 0.5,
                                 (std::get<2>(key) + 0.5) * 0.5);
    if ((centre - center).norm() <= 12) {
      ++voxels;
      kept_points += count;
    }
  }
  EXPECT_EQ(map.voxel_count(), voxels);
  EXPECT_EQ(map.point_count(), kept_points);
  EXPECT_LT(voxels, per_voxel.size() / 2);  // the test removes a lot
  const double half_diagonal = 0.5 * std::sqrt(3.0) * 0.5;
  for (const Eigen::Vector3d& p : map.Points()) EXPECT_LE((p - center).norm(), 12 + half_diagonal);
}

TEST(VoxelHashMap, PlanesFollowInserts) {
  // A floor patch gives a plane; a wall inserted through the block afterwards must change it.
  VoxelHashMap map(VoxelMapConfig{.max_range_m = 2.2});
  std::vector<Eigen::Vector3d> floor, wall;
  for (double x = -2; x <= 2; x += 0.1)
    for (double y = -2; y <= 2; y += 0.1) floor.emplace_back(x, y, 0.01);
  for (double y = -2; y <= 2; y += 0.1)
    for (double z = 0; z <= 2; z += 0.1) wall.emplace_back(0.3, y, z);
  map.Insert(floor);
  const Eigen::Vector3d query(-0.2, 0.1, 0.05);
  const Eigen::Vector3d above(-0.2, 0.1, 0.6);  // in an empty voxel whose block holds floor voxels
  const auto before = map.PlaneNear(query);
  ASSERT_TRUE(before);
  EXPECT_NEAR(std::abs(before->normal.z()), 1.0, 1e-9);
  const auto before_above = map.PlaneNear(above);
  ASSERT_TRUE(before_above);
  EXPECT_NEAR(before_above->point.z(), 0.01, 1e-9);
  map.Insert(wall);
  EXPECT_FALSE(map.PlaneNear(query));
  EXPECT_FALSE(map.PlaneNear(above));
  // Far from the wall the floor plane stays.
  EXPECT_TRUE(map.PlaneNear(Eigen::Vector3d(-1.6, 0.1, 0.05)));
  // Dropping everything farther than 2.2 m from (-2, 0, 0) removes every wall voxel (centres at x = 0.25)
  // but keeps the floor around the query: the plane comes back.
  map.RemoveFarFrom(Eigen::Vector3d(-2, 0, 0));
  const auto after = map.PlaneNear(query);
  ASSERT_TRUE(after);
  EXPECT_NEAR(std::abs(after->normal.z()), 1.0, 1e-9);
}

// The contract the ICP rounds' plane cache relies on: while revision() is unchanged, points with the same
// QueryKey get the same PlaneNear (points spread within and across voxels of the box room's walls), and
// every change of the map bumps revision().
TEST(VoxelHashMap, QueryKeyDecidesThePlaneUntilTheMapChanges) {
  const BoxRoom room;
  VoxelHashMap map;
  std::uint64_t revision = map.revision();
  map.Insert(room.Points());
  EXPECT_GT(map.revision(), revision);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  int same_key = 0;
  for (const Eigen::Vector3d& p : room.Points(0.7)) {
    const Eigen::Vector3d q = p + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    if (map.QueryKey(p) != map.QueryKey(q)) continue;
    ++same_key;
    const std::optional<Plane> a = map.PlaneNear(p), b = map.PlaneNear(q);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (a) {
      EXPECT_EQ(a->normal, b->normal);
      EXPECT_EQ(a->point, b->point);
      EXPECT_EQ(a->sigma, b->sigma);
    }
  }
  EXPECT_GT(same_key, 50);
  EXPECT_EQ(map.QueryKey(Eigen::Vector3d(std::nan(""), 0, 0)), VoxelHashMap::kNoQueryKey);
  EXPECT_EQ(map.QueryKey(Eigen::Vector3d(1e9, 0, 0)), VoxelHashMap::kNoQueryKey);
  revision = map.revision();
  map.RemoveFarFrom(Eigen::Vector3d::Zero());
  EXPECT_GT(map.revision(), revision);
  revision = map.revision();
  map.Clear();
  EXPECT_GT(map.revision(), revision);
}

TEST(VoxelHashMap, ValidatesItsConfig) {
  EXPECT_TRUE(VoxelMapConfig{}.Validate().ok());
  const Status bad = VoxelMapConfig{.voxel_m = -0.5}.Validate();
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("lidar_map.voxel_m"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("-0.5"), std::string::npos) << bad.message();
  EXPECT_FALSE(VoxelMapConfig{.max_points_per_voxel = 0}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.plane_eigen_ratio = 1.5}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.min_plane_points = 2}.Validate().ok());
  EXPECT_TRUE(VoxelMapConfig{.min_plane_rings = 0}.Validate().ok());  // auto
  EXPECT_FALSE(VoxelMapConfig{.min_plane_rings = -1}.Validate().ok());
  EXPECT_FALSE(VoxelMapConfig{.min_plane_rings = 64}.Validate().ok());
}

// ShiftedMomentSum (plane_fit.h) equals the moments of the points themselves about the common origin:
// three sets with their own origins, summed, against PointMoments built from all points directly.
TEST(ShiftedMomentSum, EqualsTheMomentsOfAllPointsAboutTheCommonOrigin) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(-0.25, 0.25);
  const Eigen::Vector3d origin(10.25, -3.75, 0.25);
  const Eigen::Vector3d own_origins[3] = {origin + Eigen::Vector3d(0.5, 0, 0), origin,
                                          origin + Eigen::Vector3d(-0.5, 0.5, -0.5)};
  PointMoments direct;
  ShiftedMomentSum sum;
  for (const Eigen::Vector3d& own : own_origins) {
    PointMoments set;
    for (int i = 0; i < 7; ++i) {
      const Eigen::Vector3d p = own + Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
      set.Add(p - own);
      direct.Add(p - origin);
    }
    sum.Add(set, own - origin);
  }
  sum.Add(PointMoments(), Eigen::Vector3d(1, 2, 3));  // empty sets add nothing
  const PointMoments total = sum.Total();
  EXPECT_EQ(total.count, direct.count);
  EXPECT_LT((total.sum - direct.sum).norm(), 1e-12);
  EXPECT_LT((total.sum_outer - direct.sum_outer).norm(), 1e-12);
}

TEST(VoxelHashMap, GroundOfAKittiScanIsPlanar) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: skipping the recorded KITTI 00 keyframes";
  auto reader = OpenDataset(std::filesystem::path(data) / "kitti00-keyframes");
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto next = (*reader)->Next();
  ASSERT_TRUE(next.ok() && *next) << (next.ok() ? "no scan" : next.error());
  const LidarScan& scan = std::get<LidarScan>((*next)->data);
  // The map in the lidar frame of this scan (the HDL-64 sits 1.73 m above the road).
  std::vector<Eigen::Vector3d> points;
  for (const LidarPoint& p : VoxelDownsample(scan.points, 0.25)) points.emplace_back(p.x, p.y, p.z);
  VoxelHashMap map;
  map.Insert(points);
  // Road, sidewalk and curbs within 10 cm of the road height: camber, curbs and the sensor's ~1-2 deg tilt
  // put most normals 0-5 deg off z (measured: 75% within 5 deg, 86% within 10 deg, 91% with a plane).
  int ground = 0, with_plane = 0, planar = 0;
  for (const LidarPoint& p : VoxelDownsample(scan.points, 0.5)) {
    const Eigen::Vector3d q(p.x, p.y, p.z);
    const double range = q.head<2>().norm();
    if (std::abs(q.z() + 1.73) > 0.1 || range < 5 || range > 20) continue;
    ++ground;
    const auto plane = map.PlaneNear(q);
    if (plane) ++with_plane;
    if (plane && std::abs(plane->normal.z()) > std::cos(10 * kPi / 180)) ++planar;
  }
  ASSERT_GT(ground, 300);
  EXPECT_GT(with_plane, 0.85 * ground) << with_plane << " of " << ground << " ground points";
  EXPECT_GT(planar, 0.8 * ground) << planar << " of " << ground << " ground points";
}

}  // namespace
}  // namespace uf::estimator
