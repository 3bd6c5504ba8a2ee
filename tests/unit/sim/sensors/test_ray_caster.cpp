// RayCaster and ParallelFor against analytic geometry and a brute-force ray/triangle reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "odometry/sim/sensors/parallel_for.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "sensor_test_scenes.h"

namespace uf::sim {
namespace {

using test::AddWallX;
using test::BoxRoomScene;

Scene WallScene(float x0) {
  Scene scene;
  AddWallX(scene.mesh, x0, -50, 50, -50, 50, Material::kBrick);
  return scene;
}

Ray MakeRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float max_range = 1e30f) {
  Ray ray;
  ray.origin = origin;
  ray.direction = direction.normalized();
  ray.max_range = max_range;
  return ray;
}

// Moeller-Trumbore: the distance along a unit ray to triangle abc, or infinity (double precision reference).
double RayTriangleDistance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-12) return INFINITY;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (u < 0 || v < 0 || u + v > 1) return INFINITY;
  const double t = e2.dot(q) / det;
  return t > 0 ? t : INFINITY;
}

TEST(RayCaster, DistanceNormalAndMaterialOfAPlaneAtKnownDistance) {
  auto caster = RayCaster::Create(WallScene(5.0f));
  ASSERT_TRUE(caster.ok()) << caster.error();
  // Straight on: distance 5, normal -x (towards the origin).
  const RayHit straight = caster->Cast(MakeRay({0, 0, 0}, {1, 0, 0}));
  ASSERT_TRUE(straight.hit());
  EXPECT_NEAR(straight.distance, 5.0f, 1e-5f);
  EXPECT_NEAR(straight.normal.x(), -1.0f, 1e-6f);
  EXPECT_NEAR(straight.normal.tail<2>().norm(), 0.0f, 1e-6f);
  EXPECT_EQ(straight.material, Material::kBrick);
  EXPECT_LT(straight.triangle, 2u);
  // Oblique at angle a from the normal: distance 5 / cos(a).
  for (const double angle : {0.3, 0.9, 1.3}) {
    const RayHit oblique = caster->Cast(
        MakeRay({0, 1, 2}, {static_cast<float>(std::cos(angle)), 0, static_cast<float>(std::sin(angle))}));
    ASSERT_TRUE(oblique.hit());
    EXPECT_NEAR(oblique.distance, 5.0 / std::cos(angle), 1e-5 * 5.0 / std::cos(angle)) << angle;
  }
  // From the other side the normal flips to face that origin.
  const RayHit behind = caster->Cast(MakeRay({12, 3, -1}, {-1, 0, 0}));
  ASSERT_TRUE(behind.hit());
  EXPECT_NEAR(behind.distance, 7.0f, 1e-5f);
  EXPECT_NEAR(behind.normal.x(), 1.0f, 1e-6f);
}

TEST(RayCaster, RayAwayFromTheGeometryMisses) {
  auto caster = RayCaster::Create(WallScene(5.0f));
  ASSERT_TRUE(caster.ok()) << caster.error();
  const RayHit miss = caster->Cast(MakeRay({0, 0, 0}, {-1, 0.2f, 0}));
  EXPECT_FALSE(miss.hit());
  EXPECT_TRUE(std::isinf(miss.distance));
  const RayHit parallel = caster->Cast(MakeRay({0, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(parallel.hit());
  const RayHit past_the_edge = caster->Cast(MakeRay({0, 0, 0}, {1, 20, 0}));  // meets x = 5 at y = 100 > 50
  EXPECT_FALSE(past_the_edge.hit());
}

TEST(RayCaster, MaxRangeIsHonoured) {
  auto caster = RayCaster::Create(WallScene(5.0f));
  ASSERT_TRUE(caster.ok()) << caster.error();
  EXPECT_FALSE(caster->Cast(MakeRay({0, 0, 0}, {1, 0, 0}, 4.99f)).hit());
  const RayHit within = caster->Cast(MakeRay({0, 0, 0}, {1, 0, 0}, 5.01f));
  ASSERT_TRUE(within.hit());
  EXPECT_NEAR(within.distance, 5.0f, 1e-5f);
}

TEST(RayCaster, RandomRaysInARoomAgreeWithBruteForceAndNormalsFaceTheOrigin) {
  const Scene scene = BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok()) << caster.error();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3f origin(uniform(rng) * 4.0f, 10.0f + uniform(rng) * 2.0f, uniform(rng));
    Eigen::Vector3f direction(uniform(rng), uniform(rng), uniform(rng));
    if (direction.norm() < 0.1f) continue;
    const Ray ray = MakeRay(origin, direction);
    const RayHit hit = caster->Cast(ray);
    // Reference: the nearest triangle by brute force, in double precision.
    double truth = INFINITY;
    std::size_t truth_triangle = 0;
    for (std::size_t t = 0; t < scene.mesh.triangles.size(); ++t) {
      const Eigen::Vector3i& tri = scene.mesh.triangles[t];
      const double d = RayTriangleDistance(
          ray.origin.cast<double>(), ray.direction.cast<double>(), scene.mesh.vertices[tri[0]].cast<double>(),
          scene.mesh.vertices[tri[1]].cast<double>(), scene.mesh.vertices[tri[2]].cast<double>());
      if (d < truth) truth = d, truth_triangle = t;
    }
    ASSERT_TRUE(std::isfinite(truth));  // the room is closed
    ASSERT_TRUE(hit.hit()) << i;
    ++hits;
    EXPECT_NEAR(hit.distance, truth, 1e-4) << i;
    EXPECT_LT(hit.normal.dot(ray.direction), 0.0f) << i;
    EXPECT_NEAR(hit.normal.norm(), 1.0f, 1e-5f);
    EXPECT_EQ(hit.material, scene.mesh.materials[truth_triangle]) << i;
    // The normal is the triangle's plane normal (up to sign).
    const Eigen::Vector3i& tri = scene.mesh.triangles[hit.triangle];
    const Eigen::Vector3f n = (scene.mesh.vertices[tri[1]] - scene.mesh.vertices[tri[0]])
                                  .cross(scene.mesh.vertices[tri[2]] - scene.mesh.vertices[tri[0]])
                                  .normalized();
    EXPECT_NEAR(std::abs(n.dot(hit.normal)), 1.0f, 1e-5f);
  }
  EXPECT_GT(hits, 1900);
}

TEST(RayCaster, BatchCastIsIdenticalForAnyThreadCount) {
  auto caster = RayCaster::Create(BoxRoomScene());
  ASSERT_TRUE(caster.ok()) << caster.error();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<Ray> rays(20000);
  for (Ray& ray : rays) {
    ray = MakeRay({uniform(rng), uniform(rng), uniform(rng)},
                  {uniform(rng), uniform(rng), uniform(rng) + 1e-3f}, 25.0f);
  }
  const auto cast_with = [&](int threads) {
    std::vector<RayHit> hits(rays.size());
    ParallelFor(rays.size(), threads, [&](std::size_t begin, std::size_t end) {
      caster->Cast(std::span<const Ray>(rays).subspan(begin, end - begin),
                   std::span<RayHit>(hits).subspan(begin, end - begin));
    });
    return hits;
  };
  const std::vector<RayHit> one = cast_with(1);
  int misses = 0;
  for (const RayHit& h : one) misses += !h.hit();
  EXPECT_GT(misses, 0);  // some rays are longer than 25 m: max_range applies in batches too
  for (const int threads : {2, 3, 8}) {
    const std::vector<RayHit> many = cast_with(threads);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(std::memcmp(&one[i].distance, &many[i].distance, sizeof(float)), 0) << i;
      ASSERT_EQ(one[i].normal, many[i].normal) << i;
      ASSERT_EQ(one[i].triangle, many[i].triangle) << i;
      ASSERT_EQ(one[i].material, many[i].material) << i;
    }
  }
}

TEST(RayCaster, AHitDependsOnlyOnItsRayNotOnTheBatchAroundIt) {
  // Rays are cast in packets: a ray alone, or at any position in a batch, gives the same bits.
  auto caster = RayCaster::Create(BoxRoomScene());
  ASSERT_TRUE(caster.ok()) << caster.error();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<Ray> rays(3001);
  for (Ray& ray : rays) {
    ray = MakeRay({uniform(rng) * 3, 10 + uniform(rng), uniform(rng)},
                  {uniform(rng), uniform(rng), uniform(rng)});
  }
  std::vector<RayHit> batch(rays.size());
  caster->Cast(rays, batch);
  for (const std::size_t shift : {1u, 3u, 5u}) {
    std::vector<RayHit> shifted(rays.size() - shift);
    caster->Cast(std::span<const Ray>(rays).subspan(shift), shifted);
    for (std::size_t i = 0; i < shifted.size(); ++i) {
      ASSERT_EQ(std::memcmp(&shifted[i].distance, &batch[i + shift].distance, sizeof(float)), 0) << i;
      ASSERT_EQ(shifted[i].normal, batch[i + shift].normal) << i;
      ASSERT_EQ(shifted[i].triangle, batch[i + shift].triangle) << i;
    }
  }
  for (std::size_t i = 0; i < rays.size(); i += 97) {
    const RayHit alone = caster->Cast(rays[i]);
    ASSERT_EQ(std::memcmp(&alone.distance, &batch[i].distance, sizeof(float)), 0) << i;
    ASSERT_EQ(alone.normal, batch[i].normal) << i;
  }
}

TEST(RayCaster, BadMeshesGiveErrorsNamingTheProblem) {
  Scene empty;
  auto result = RayCaster::Create(empty);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("empty"), std::string::npos) << result.error();

  Scene nan_vertex = WallScene(1.0f);
  nan_vertex.mesh.vertices[2].y() = std::nanf("");
  result = RayCaster::Create(nan_vertex);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("vertex 2"), std::string::npos) << result.error();

  Scene bad_index = WallScene(1.0f);
  bad_index.mesh.triangles[1][2] = 4;
  result = RayCaster::Create(bad_index);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("triangle 1 has vertex index 4, out of range [0, 4)"), std::string::npos)
      << result.error();

  Scene negative_index = WallScene(1.0f);
  negative_index.mesh.triangles[0][0] = -1;
  result = RayCaster::Create(negative_index);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("triangle 0 has vertex index -1"), std::string::npos) << result.error();

  Scene missing_material = WallScene(1.0f);
  missing_material.mesh.materials.pop_back();
  result = RayCaster::Create(missing_material);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("materials has 1 entries"), std::string::npos) << result.error();
}

TEST(RayCaster, MovedCasterStillWorks) {
  auto created = RayCaster::Create(WallScene(3.0f));
  ASSERT_TRUE(created.ok()) << created.error();
  RayCaster moved = std::move(created.value());
  RayCaster assigned = std::move(moved);
  EXPECT_NEAR(assigned.Cast(MakeRay({0, 0, 0}, {1, 0, 0})).distance, 3.0f, 1e-5f);
}

TEST(ParallelFor, EveryIndexIsVisitedExactlyOnceInContiguousChunks) {
  for (const std::size_t count : {0u, 1u, 5u, 1000u}) {
    for (const int threads : {-1, 0, 1, 3, 16}) {
      std::vector<int> visits(count, 0);
      ParallelFor(count, threads, [&](std::size_t begin, std::size_t end) {
        ASSERT_LT(begin, end);
        for (std::size_t i = begin; i < end; ++i) ++visits[i];
      });
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(visits[i], 1) << count << " " << threads << " " << i;
    }
  }
  EXPECT_EQ(ResolveThreadCount(3), 3);
  EXPECT_GE(ResolveThreadCount(0), 1);
}

}  // namespace
}  // namespace uf::sim
