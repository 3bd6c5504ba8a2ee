// The global map on the simulated urban scene with ground-truth poses: three LiDAR sweeps, each point moved
// to the world frame with the true pose at its own time, inserted; >= 99 % of the MapView points must lie
// within 2 voxels of the true scene surface. The reference distance is point-to-nearest-triangle over the
// scene mesh, with the triangles bucketed in a uniform 1 m grid (exact for distances below the bucket
// margin, which is all the test asks about).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "mapping/global_map.h"
#include "mapping/map_view.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sensors/lidar_model.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sim_trajectory.h"
#include "tests/support/triangle_distance.h"

namespace uf::mapping {
namespace {

using uf::testing::PointTriangleDistance;

// Triangles bucketed by the 1 m cells their bounding box, grown by `margin`, overlaps (inside `region`
// only). Distance(p) is exact whenever the true distance is below `margin`, and >= margin otherwise.
class TriangleGrid {
 public:
  TriangleGrid(const sim::TriangleMesh& mesh, const Eigen::AlignedBox3d& region, double margin)
      : mesh_(mesh), margin_(margin) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      Eigen::AlignedBox3d box;
      for (int k = 0; k < 3; ++k)
        box.extend(mesh.vertices[static_cast<std::size_t>(mesh.triangles[t](k))].cast<double>());
      box.min().array() -= margin;
      box.max().array() += margin;
      box = box.intersection(region);
      if (box.isEmpty()) continue;
      const Eigen::Vector3i lo = Cell(box.min()), hi = Cell(box.max());
      for (int x = lo.x(); x <= hi.x(); ++x)
        for (int y = lo.y(); y <= hi.y(); ++y)
          for (int z = lo.z(); z <= hi.z(); ++z) cells_[Key(Eigen::Vector3i(x, y, z))].push_back(t);
    }
  }

  double Distance(const Eigen::Vector3d& p) const {
    const auto it = cells_.find(Key(Cell(p)));
    double best = margin_;
    if (it == cells_.end()) return best;
    for (const std::size_t t : it->second) {
      const Eigen::Vector3i& tri = mesh_.triangles[t];
      best = std::min(best, PointTriangleDistance(p, Vertex(tri(0)), Vertex(tri(1)), Vertex(tri(2))));
    }
    return best;
  }

 private:
  static Eigen::Vector3i Cell(const Eigen::Vector3d& p) { return p.array().floor().cast<int>(); }
  static std::int64_t Key(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x() + (1 << 20)) << 42) |
           (static_cast<std::int64_t>(c.y() + (1 << 20)) << 21) |
           static_cast<std::int64_t>(c.z() + (1 << 20));
  }
  Eigen::Vector3d Vertex(int i) const { return mesh_.vertices[static_cast<std::size_t>(i)].cast<double>(); }

  const sim::TriangleMesh& mesh_;
  double margin_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

TEST(GlobalMapSim, UrbanPointsLieOnTheTrueSurfaces) {
  sim::SimulationConfig config;  // urban, spinning32 at 10 Hz, 2 cm range noise
  config.duration_s = 6.0;
  auto motion = sim::MakeSimulationTrajectory(config);
  ASSERT_TRUE(motion.ok()) << motion.error();
  auto scene =
      sim::BuildScene({config.scene, config.seed, motion->poses, config.body_height_m, config.origin});
  ASSERT_TRUE(scene.ok()) << scene.error();
  auto caster = sim::RayCaster::Create(*scene);
  ASSERT_TRUE(caster.ok()) << caster.error();
  const SE3& T_body_lidar = config.lidar.placement.T_body_sensor;
  auto lidar = sim::LidarSimulator::Create(config.lidar.model, *caster, motion->spline, T_body_lidar, 11);
  ASSERT_TRUE(lidar.ok()) << lidar.error();

  GlobalMapConfig map_config;  // 5 cm voxels, the defaults
  auto map = GlobalMap::Create(map_config);
  ASSERT_TRUE(map.ok());
  std::size_t inserted = 0;
  for (const double t : {4.0, 4.5, 5.0}) {  // at speed: without per-point poses ~7 % miss
    auto scan = lidar->Scan(motion->begin + FromSeconds(t));
    ASSERT_TRUE(scan.ok()) << scan.error();
    std::vector<Eigen::Vector3f> world;
    std::vector<float> intensity;
    for (const LidarPoint& p : scan->points) {
      const SE3 T_world_lidar = motion->spline.Pose(scan->stamp + p.offset_ns) * T_body_lidar;
      world.push_back((T_world_lidar * Eigen::Vector3d(p.x, p.y, p.z)).cast<float>());
      intensity.push_back(p.intensity);
    }
    const Eigen::Vector3d origin =
        (motion->spline.Pose((scan->stamp + scan->end) / 2) * T_body_lidar).translation();
    ASSERT_TRUE(map->Insert(WorldScan{scan->end, origin, world, intensity, {}}).ok());
    inserted += world.size();
  }
  ASSERT_GT(inserted, 50000u);

  const MapView view(*map, {65536, false});
  ASSERT_GT(view.size(), 20000u);
  Eigen::AlignedBox3d region = view.bounds();
  region.min().array() -= 1.0;
  region.max().array() += 1.0;
  const double tolerance = 2 * map_config.voxel_size_m;
  const TriangleGrid grid(scene->mesh, region, 2 * tolerance);
  std::size_t near = 0;
  view.ForEachChunk([&](std::span<const MapPoint> chunk) {
    for (const MapPoint& p : chunk) near += grid.Distance(p.position) <= tolerance ? 1 : 0;
    return true;
  });
  const double fraction = static_cast<double>(near) / static_cast<double>(view.size());
  RecordProperty("map_points", static_cast<int>(view.size()));
  RecordProperty("fraction_within_2_voxels_permille", static_cast<int>(1000 * fraction));
  EXPECT_GE(fraction, 0.99) << near << " of " << view.size();
}

}  // namespace
}  // namespace uf::mapping
