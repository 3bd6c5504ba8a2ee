// GlobalMap and MapView on hand-built inserts: merging (mean position, count, colour, intensity, stamp),
// colour outlier rejection, the noise filter, NaN handling, bounded memory, normals, queries and chunking,
// each against values worked out by hand or by brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "mapping/global_map.h"
#include "mapping/map_view.h"
#include "tests/unit/mapping/map_test_support.h"

namespace uf::mapping {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

GlobalMap MakeMap(GlobalMapConfig config = {}) {
  auto map = GlobalMap::Create(config);
  EXPECT_TRUE(map.ok()) << map.error();
  return std::move(map).value();
}

using ::uf::mapping::testing::AllPoints;

Status InsertOne(GlobalMap& map, Stamp stamp, const Eigen::Vector3f& p, float intensity = 0,
                 PointColor color = std::nullopt) {
  const std::vector<Eigen::Vector3f> points = {p};
  const std::vector<float> intensities = {intensity};
  const std::vector<PointColor> colors = {color};
  return map.Insert(WorldScan{stamp, Eigen::Vector3d(0, 0, 10), points, intensities, colors});
}

TEST(GlobalMapConfig, ValidateNamesFieldAndValue) {
  EXPECT_TRUE(GlobalMapConfig{}.Validate().ok());
  GlobalMapConfig config;
  config.voxel_size_m = -1;
  EXPECT_NE(config.Validate().message().find("map.voxel_size_m"), std::string::npos);
  EXPECT_NE(config.Validate().message().find("-1"), std::string::npos);
  config = {};
  config.min_observations = 0;
  EXPECT_NE(config.Validate().message().find("map.min_observations"), std::string::npos);
  config = {};
  config.color_outlier_sigma = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(config.Validate().message().find("map.color_outlier_sigma"), std::string::npos);
  config = {};
  config.max_voxels = 0;
  EXPECT_FALSE(GlobalMap::Create(config).ok());
}

TEST(GlobalMap, TwoPointsInAVoxelGiveTheirMean) {
  GlobalMapConfig config;
  config.voxel_size_m = 0.1;  // voxel (1, 2, 3) covers [0.05, 0.15) x [0.15, 0.25) x [0.25, 0.35)
  GlobalMap map = MakeMap(config);
  ASSERT_TRUE(InsertOne(map, 100, {0.06f, 0.16f, 0.26f}, 10.0f, Rgb{10, 20, 30}).ok());
  EXPECT_EQ(MapView(map).size(), 0u);  // seen once, no neighbours
  ASSERT_TRUE(InsertOne(map, 200, {0.14f, 0.24f, 0.34f}, 30.0f, Rgb{30, 40, 51}).ok());
  const MapView view(map);
  ASSERT_EQ(view.size(), 1u);
  const MapPoint p = AllPoints(view).at(0);
  EXPECT_NEAR(p.position.x(), 0.10, 1e-6);
  EXPECT_NEAR(p.position.y(), 0.20, 1e-6);
  EXPECT_NEAR(p.position.z(), 0.30, 1e-6);
  EXPECT_EQ(p.count, 2u);
  EXPECT_FLOAT_EQ(p.intensity, 20.0f);
  EXPECT_EQ(p.last_stamp, 200);
  EXPECT_TRUE(p.has_color);
  EXPECT_EQ(p.rgb, (Rgb{20, 30, 41}));  // (30 + 51) / 2 = 40.5 rounds to 41
  EXPECT_EQ(map.stats().points_inserted, 2u);
}

TEST(GlobalMap, RejectsOutlierColours) {
  GlobalMap map = MakeMap();
  const Eigen::Vector3f p(1.0f, 1.0f, 1.0f);
  for (const Rgb& c : {Rgb{100, 100, 100}, Rgb{102, 98, 100}, Rgb{98, 102, 100}})
    ASSERT_TRUE(InsertOne(map, 1, p, 0, c).ok());
  // sigma = sqrt((8 + 8) / 2) ~ 2.8 < floor 20: gate 3 * 20 = 60. (250, 0, 0) is 180 away: rejected.
  ASSERT_TRUE(InsertOne(map, 2, p, 0, Rgb{250, 0, 0}).ok());
  EXPECT_EQ(map.stats().colors_rejected, 1u);
  // (108, 100, 100) is 8 away: accepted, mean (408 / 4, 400 / 4, 400 / 4) = (102, 100, 100).
  ASSERT_TRUE(InsertOne(map, 3, p, 0, Rgb{108, 100, 100}).ok());
  // An uncoloured observation counts as an observation but leaves the colour alone.
  ASSERT_TRUE(InsertOne(map, 4, p, 0, std::nullopt).ok());
  const auto points = AllPoints(MapView(map));
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].rgb, (Rgb{102, 100, 100}));
  EXPECT_EQ(points[0].count, 6u);
  EXPECT_EQ(map.stats().colors_rejected, 1u);
}

TEST(GlobalMap, OnceSeenPointsNeedNeighbours) {
  GlobalMapConfig config;
  config.voxel_size_m = 0.1;
  GlobalMap map = MakeMap(config);
  // An isolated once-seen point, and a scan line of 5 once-seen voxels in a row along x.
  ASSERT_TRUE(InsertOne(map, 1, {5.0f, 5.0f, 5.0f}).ok());
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(InsertOne(map, 1, {0.1f * static_cast<float>(i), 0.0f, 0.0f}).ok());
  // The line's 3 inner voxels have 2 occupied neighbours each (>= min_neighbors_if_unconfirmed = 2), its
  // ends only 1; the isolated point none.
  const auto points = AllPoints(MapView(map));
  ASSERT_EQ(points.size(), 3u);
  for (const MapPoint& p : points) {
    EXPECT_GT(p.position.x(), 0.05);
    EXPECT_LT(p.position.x(), 0.35);
  }
  config.min_neighbors_if_unconfirmed = 27;  // off: only confirmed voxels
  GlobalMap strict = MakeMap(config);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(InsertOne(strict, 1, {0.1f * static_cast<float>(i), 0, 0}).ok());
  EXPECT_EQ(MapView(strict).size(), 0u);
}

TEST(GlobalMap, SkipsAndCountsNonFinitePoints) {
  GlobalMap map = MakeMap();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<Eigen::Vector3f> points = {{1, 1, 1}, {nan, 0, 0}, {1, 1, 1}, {0, inf, 0}, {0, 0, 1e30f}};
  ASSERT_TRUE(map.Insert(WorldScan{1, Eigen::Vector3d::Zero(), points, {}, {}}).ok());
  EXPECT_EQ(map.stats().points_skipped_invalid, 3u);  // NaN, Inf, and 1e30 beyond the index range
  EXPECT_EQ(map.stats().points_inserted, 2u);
  EXPECT_EQ(map.size(), 1u);
  // Wrong attribute lengths are an error and insert nothing.
  const std::vector<float> two = {1, 2};
  const Status bad = map.Insert(WorldScan{2, Eigen::Vector3d::Zero(), points, two, {}});
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("2 intensities for 5 points"), std::string::npos);
  EXPECT_EQ(map.stats().points_inserted, 2u);
}

TEST(GlobalMap, KeepsPositionPrecisionFarFromTheOrigin) {
  GlobalMap map = MakeMap();
  // Float inputs near x = 50 km (spacing 1/256 m there); the mean must be exact to well below that.
  const std::vector<Eigen::Vector3f> points = {{50000.0f, 3.0f, 1.0f}, {50000.0078125f, 3.01f, 1.02f}};
  ASSERT_TRUE(map.Insert(WorldScan{1, Eigen::Vector3d::Zero(), points, {}, {}}).ok());
  const auto view = AllPoints(MapView(map));
  ASSERT_EQ(view.size(), 1u);
  const Eigen::Vector3d mean = (points[0].cast<double>() + points[1].cast<double>()) / 2.0;
  EXPECT_NEAR((view[0].position - mean).norm(), 0.0, 1e-5);
}

// Scans k = 0..9 at stamps k, each 30 new voxels along +x at increasing distance from the sensor.
TEST(GlobalMap, BoundedMemoryDropsOldestThenFarthest) {
  GlobalMapConfig config;
  config.voxel_size_m = 0.1;
  config.max_voxels = 100;
  config.min_observations = 1;
  GlobalMap map = MakeMap(config);
  std::map<Stamp, std::vector<double>> inserted;  // stamp -> x of its voxels
  for (int k = 0; k < 10; ++k) {
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 30; ++i) {
      const float x = 0.1f * static_cast<float>(i);
      points.emplace_back(x, 0.1f * static_cast<float>(k), 0.0f);
      inserted[k].push_back(x);
    }
    ASSERT_TRUE(map.Insert(WorldScan{k, Eigen::Vector3d(-1, 0, 0), points, {}, {}}).ok());
    EXPECT_LE(map.size(), 100u);
  }
  std::map<Stamp, std::vector<double>> kept;
  for (const MapPoint& p : AllPoints(MapView(map))) kept[p.last_stamp].push_back(p.position.x());
  // Newest first: every scan newer than a partly kept one is complete, every older one is gone.
  Stamp partial = -1;
  for (Stamp k = 9; k >= 0; --k) {
    const std::size_t n = kept.count(k) ? kept[k].size() : 0;
    if (partial < 0 && n < 30) partial = k;
    if (partial < 0) {
      EXPECT_EQ(n, 30u) << "scan " << k;
    }
    if (partial >= 0 && k < partial) {
      EXPECT_EQ(n, 0u) << "scan " << k;
    }
  }
  ASSERT_GE(partial, 0);
  // In the partly kept scan, the kept voxels are the nearest to the sensor (x = -1): x below a cut.
  auto& xs = kept[partial];
  std::sort(xs.begin(), xs.end());
  for (std::size_t i = 0; i < xs.size(); ++i) EXPECT_NEAR(xs[i], 0.1 * static_cast<double>(i), 1e-5);
  const GlobalMapStats stats = map.stats();
  EXPECT_EQ(stats.voxels_evicted + stats.voxels, 300u);
  EXPECT_GT(stats.memory_bytes, 0u);
}

// A dense patch of the plane z = 0 seen from above (or below): normals +z (or -z).
TEST(MapView, NormalsOfAPlaneFaceTheSensor) {
  for (const double sensor_z : {5.0, -5.0}) {
    GlobalMapConfig config;
    config.voxel_size_m = 0.1;
    config.min_observations = 1;
    GlobalMap map = MakeMap(config);
    std::vector<Eigen::Vector3f> points;
    for (int i = -10; i <= 10; ++i)
      for (int j = -10; j <= 10; ++j)
        points.emplace_back(0.1f * i + 0.01f * (j % 3), 0.1f * j, 0.003f * (i % 2));
    ASSERT_TRUE(map.Insert(WorldScan{1, Eigen::Vector3d(0, 0, sensor_z), points, {}, {}}).ok());
    const auto view = AllPoints(MapView(map));
    ASSERT_EQ(view.size(), points.size());
    for (const MapPoint& p : view) EXPECT_NEAR(p.normal.z(), sensor_z > 0 ? 1.0 : -1.0, 1e-3);
    // Without normals: zero.
    for (const MapPoint& p : AllPoints(MapView(map, {65536, false}))) EXPECT_EQ(p.normal.norm(), 0.0f);
  }
}

TEST(MapView, QueriesAndChunksMatchBruteForce) {
  GlobalMapConfig config;
  config.voxel_size_m = 0.2;
  config.min_observations = 1;
  GlobalMap map = MakeMap(config);
  std::mt19937_64 engine(7);
  std::uniform_real_distribution<float> uniform(-3.0f, 3.0f);
  std::vector<Eigen::Vector3f> points(3000);
  std::vector<PointColor> colors(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float x = uniform(engine), y = uniform(engine), z = uniform(engine);
    points[i] = Eigen::Vector3f(x, y, z);
    if (i % 3 == 0) colors[i] = Rgb{1, 2, 3};
  }
  ASSERT_TRUE(map.Insert(WorldScan{1, Eigen::Vector3d::Zero(), points, {}, colors}).ok());
  const MapView view(map, {7, false});
  std::vector<MapPoint> all;
  std::size_t chunks = 0;
  view.ForEachChunk([&](std::span<const MapPoint> chunk) {
    EXPECT_LE(chunk.size(), 7u);
    all.insert(all.end(), chunk.begin(), chunk.end());
    return ++chunks < 1000000;
  });
  ASSERT_EQ(all.size(), view.size());
  ASSERT_EQ(all.size(), map.size());
  Eigen::AlignedBox3d box;
  for (const MapPoint& p : all) box.extend(p.position);
  EXPECT_TRUE(box.isApprox(view.bounds()));
  std::size_t calls = 0;
  EXPECT_FALSE(view.ForEachChunk([&](std::span<const MapPoint>) { return ++calls < 3; }));
  EXPECT_EQ(calls, 3u);

  for (int q = 0; q < 50; ++q) {
    const float qx = uniform(engine), qy = uniform(engine), qz = uniform(engine);
    const Eigen::Vector3d query = Eigen::Vector3f(qx, qy, qz).cast<double>();
    for (const bool color : {false, true}) {
      double best = 0.5;
      const MapPoint* expected = nullptr;
      std::size_t within = 0;
      for (const MapPoint& p : all) {
        const double d = (p.position - query).norm();
        within += d <= 0.5 ? 1 : 0;
        if ((!color || p.has_color) && d <= best) best = d, expected = &p;
      }
      const auto found = view.Nearest(query, 0.5, color);
      ASSERT_EQ(found.has_value(), expected != nullptr);
      if (found) {
        EXPECT_EQ(found->position, expected->position);
      }
      if (!color) {
        EXPECT_EQ(view.RadiusSearch(query, 0.5).size(), within);
      }
    }
  }
}

}  // namespace
}  // namespace uf::mapping
