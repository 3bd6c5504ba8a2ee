// BuildScene: every scene's mesh is well formed, seeded, keeps the track clear, has its ground under the
// track at the body height, and (corridor, tunnel) encloses the track. Truth by brute force over triangles.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/scene/scene_builder.h"
#include "tests/support/triangle_distance.h"

namespace uf::sim {
namespace {

using uf::testing::PointTriangleDistance;

using Eigen::Vector3d;

// Nearest hit distance of the ray o + t d (t > 0) with the mesh (Moller-Trumbore), if any; triangles of
// material `ignore` are skipped.
std::optional<double> Raycast(const TriangleMesh& mesh, const Vector3d& o, const Vector3d& d,
                              Material ignore = Material::kCount) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < mesh.triangle_count(); ++k) {
    if (mesh.materials[k] == ignore) continue;
    const Eigen::Vector3i& tri = mesh.triangles[k];
    const Vector3d a = mesh.vertices[tri[0]].cast<double>(), b = mesh.vertices[tri[1]].cast<double>();
    const Vector3d c = mesh.vertices[tri[2]].cast<double>();
    const Vector3d e1 = b - a, e2 = c - a, h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-12) continue;
    const Vector3d s = o - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    const double t = e2.dot(q) / det;
    if (t > 1e-6 && t < best) best = t;
  }
  if (std::isinf(best)) return std::nullopt;
  return best;
}

Trajectory DefaultTrajectory(const std::string& name, double duration_s) {
  auto t = DefaultSceneTrajectory(name, duration_s, 5, 0);
  EXPECT_TRUE(t.ok()) << t.error();
  return *t;
}

SceneOptions Options(const std::string& name, std::uint64_t seed, double duration_s = 30.0) {
  SceneOptions options;
  options.name = name;
  options.seed = seed;
  options.trajectory = DefaultTrajectory(name, duration_s);
  options.body_height_m = 1.7;
  return options;
}

class EveryScene : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryScene, WellFormedSeededAndClearOfTheTrack) {
  const SceneOptions options = Options(GetParam(), 11);
  const auto scene = BuildScene(options);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const TriangleMesh& mesh = scene->mesh;
  EXPECT_EQ(scene->name, GetParam());
  EXPECT_EQ(scene->origin.latitude_deg, options.origin.latitude_deg);
  ASSERT_GT(mesh.triangle_count(), 500u);
  ASSERT_EQ(mesh.materials.size(), mesh.triangle_count());
  for (const Eigen::Vector3f& v : mesh.vertices) ASSERT_TRUE(v.allFinite());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    ASSERT_TRUE((t.array() >= 0).all() && (t.array() < static_cast<int>(mesh.vertices.size())).all());
  }
  for (const Material m : mesh.materials) ASSERT_LT(static_cast<int>(m), static_cast<int>(Material::kCount));

  // Same seed: identical; another seed: different (corridor and tunnel have no random content).
  const auto again = BuildScene(options);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->mesh.vertices, mesh.vertices);
  EXPECT_EQ(again->mesh.triangles, mesh.triangles);
  if (GetParam() != "corridor" && GetParam() != "tunnel") {
    SceneOptions other = options;
    other.seed = 12;
    EXPECT_NE(BuildScene(other)->mesh.vertices, mesh.vertices);
  }

  // Within the clearance (3D distance) of any trajectory sample there is nothing but ground: every vertex of
  // such a triangle lies at most a curb (0.12 m) plus paint above the ground level (z - body height) of the
  // trajectory pose nearest to it in xy (brute force over all poses).
  const double clearance = SceneClearance(GetParam()) - 0.05;
  const Trajectory& trajectory = options.trajectory;
  auto ground_under = [&](const Vector3d& v) {
    double best = std::numeric_limits<double>::infinity(), z = 0.0;
    for (const SE3& pose : trajectory.poses) {
      const double d = (pose.translation() - v).head<2>().squaredNorm();
      if (d < best) best = d, z = pose.translation().z();
    }
    return z - options.body_height_m;
  };
  // The nearest non-ground triangle must exist just outside the clearance, so that the check can fail.
  double nearest_object = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < trajectory.size(); i += 50) {
    const Vector3d p = trajectory.poses[i].translation();
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      const Vector3d a = mesh.vertices[mesh.triangles[t][0]].cast<double>();
      if ((a - p).norm() > 60.0) continue;  // no triangle of these scenes is 60 m across near the track
      const Vector3d b = mesh.vertices[mesh.triangles[t][1]].cast<double>();
      const Vector3d c = mesh.vertices[mesh.triangles[t][2]].cast<double>();
      const double distance = PointTriangleDistance(p, a, b, c);
      if (distance >= clearance + 2.0) continue;
      bool ground = true;
      for (const Vector3d& v : {a, b, c}) ground = ground && v.z() <= ground_under(v) + 0.15;
      if (!ground) nearest_object = std::min(nearest_object, distance);
      EXPECT_TRUE(ground || distance >= clearance)
          << GetParam() << ": material " << AppearanceOf(mesh.materials[t]).name << " near sample " << i;
    }
  }
  EXPECT_LT(nearest_object, clearance + 2.0) << GetParam();

  // Straight down from the body: the ground (road, floor, terrain) at the body height.
  for (std::size_t i = 0; i < trajectory.size(); i += 250) {
    const Vector3d p = trajectory.poses[i].translation();
    const auto down = Raycast(mesh, p, {0, 0, -1});
    ASSERT_TRUE(down.has_value()) << GetParam() << " sample " << i;
    EXPECT_NEAR(*down, options.body_height_m, 0.06) << GetParam() << " sample " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EveryScene,
                         ::testing::Values("urban", "wild", "warehouse", "corridor", "tunnel"));

// Horizontal distance to the walls left and right of the body, and up to the ceiling.
void ExpectEnclosed(const std::string& name, double left_right, double up, double tolerance) {
  const SceneOptions options = Options(name, 3);
  const auto scene = BuildScene(options);
  ASSERT_TRUE(scene.ok());
  const Trajectory& trajectory = options.trajectory;
  for (std::size_t i = 0; i < trajectory.size(); i += 300) {
    const SE3& pose = trajectory.poses[i];
    const Vector3d p = pose.translation();
    // Horizontal left direction of the track at this pose: z x (body x projected on the ground).
    Vector3d forward = pose.rotation().col(0);
    forward.z() = 0.0;
    const Vector3d left = Vector3d::UnitZ().cross(forward.normalized());
    for (const Vector3d& d : {left, Vector3d(-left)}) {
      const auto hit = Raycast(scene->mesh, p, d);
      ASSERT_TRUE(hit.has_value()) << name << " sample " << i;
      EXPECT_NEAR(*hit, left_right, tolerance) << name << " sample " << i;
    }
    const auto ceiling = Raycast(scene->mesh, p, Vector3d::UnitZ(), Material::kMetal);  // not the lamps
    ASSERT_TRUE(ceiling.has_value());
    EXPECT_NEAR(*ceiling, up, tolerance) << name << " sample " << i;
  }
}

TEST(BuildScene, CorridorEnclosesTheTrack) {
  // 2.5 m wide, 3 m high, body 1.7 m above the floor.
  ExpectEnclosed("corridor", 1.25, 3.0 - 1.7, 0.05);
}

TEST(BuildScene, TunnelEnclosesTheTrack) {
  // Circle of radius 5.5 centred 1.5 m above the road: at 1.7 m, walls at sqrt(5.5^2 - 0.2^2); the crown
  // at 7.0 m above the road (minus the 28-gon's sagitta, up to R (1 - cos(pi / 28)) = 3.5 cm, on the sides).
  ExpectEnclosed("tunnel", std::sqrt(5.5 * 5.5 - 0.2 * 0.2), 7.0 - 1.7, 0.06);
}

TEST(BuildScene, UrbanBudget) {
  // A 60 s default urban drive (~450 m): well below ~1 M triangles (the CLI's budget; time is reported
  // by the tool, not asserted).
  const auto scene = BuildScene(Options("urban", 1, 60.0));
  ASSERT_TRUE(scene.ok());
  EXPECT_LT(scene->mesh.triangle_count(), 1'000'000u);
}

TEST(BuildScene, BadInput) {
  SceneOptions options = Options("urban", 1, 5.0);
  options.name = "moon";
  auto scene = BuildScene(options);
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().find("moon"), std::string::npos);
  for (const std::string_view name : SceneNames()) {
    EXPECT_NE(scene.error().find(std::string(name)), std::string::npos);
  }
  options.name = "urban";
  options.trajectory.poses.resize(1);
  options.trajectory.stamps.resize(1);
  scene = BuildScene(options);
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().find("at least 2 poses"), std::string::npos);
  options = Options("urban", 1, 5.0);
  options.trajectory.stamps.clear();
  scene = BuildScene(options);
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().find("stamp"), std::string::npos);
  options = Options("urban", 1, 5.0);
  options.body_height_m = -1.0;
  EXPECT_FALSE(BuildScene(options).ok());
}

TEST(BuildScene, SelfCrossingTrackStaysClear) {
  // A figure-eight track: objects laid out along one branch must not land on the other.
  Trajectory eight;
  for (int i = 0; i <= 2000; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 2000.0;
    eight.stamps.push_back(i * 10'000'000LL);
    const Vector3d p(60.0 * std::sin(a), 30.0 * std::sin(2.0 * a), 1.8);
    const Vector3d v(60.0 * std::cos(a), 60.0 * std::cos(2.0 * a), 0.0);
    eight.poses.emplace_back(SO3::Exp({0, 0, std::atan2(v.y(), v.x())}), p);
  }
  SceneOptions options;
  options.name = "urban";
  options.trajectory = eight;
  const auto scene = BuildScene(options);
  ASSERT_TRUE(scene.ok());
  for (std::size_t i = 0; i < eight.size(); i += 40) {
    const Vector3d p = eight.poses[i].translation();
    for (std::size_t t = 0; t < scene->mesh.triangle_count(); ++t) {
      const auto& tri = scene->mesh.triangles[t];
      const Vector3d a = scene->mesh.vertices[tri[0]].cast<double>();
      if ((a - p).norm() > 60.0) continue;
      const Vector3d b = scene->mesh.vertices[tri[1]].cast<double>(),
                     c = scene->mesh.vertices[tri[2]].cast<double>();
      if (PointTriangleDistance(p, a, b, c) < 2.9) {
        ASSERT_LE(std::max({a.z(), b.z(), c.z()}), 0.15) << i;
      }
    }
  }
}

}  // namespace
}  // namespace uf::sim
