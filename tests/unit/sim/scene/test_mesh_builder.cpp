// MeshBuilder: triangle counts, and outward orientation through the divergence theorem (the signed volume
// of a closed mesh equals its analytic volume only if every normal points outwards).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "odometry/sim/scene/mesh_builder.h"

namespace uf::sim {
namespace {

Eigen::Vector3d Normal(const TriangleMesh& mesh, std::size_t t) {
  const Eigen::Vector3i& tri = mesh.triangles[t];
  const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>(), b = mesh.vertices[tri[1]].cast<double>();
  const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>();
  return (b - a).cross(c - a);
}

TEST(MeshBuilder, QuadIsCounterClockwiseFromTheFront) {
  TriangleMesh mesh;
  MeshBuilder(mesh).AddQuad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, Material::kAsphalt);
  ASSERT_EQ(mesh.triangle_count(), 2u);
  ASSERT_EQ(mesh.materials.size(), 2u);
  for (std::size_t t = 0; t < 2; ++t) EXPECT_GT(Normal(mesh, t).z(), 0.0);  // seen from +z: CCW
  // Total area 1.
  EXPECT_NEAR(0.5 * (Normal(mesh, 0).norm() + Normal(mesh, 1).norm()), 1.0, 1e-6);
}

TEST(MeshBuilder, BoxVolumeAndCount) {
  TriangleMesh mesh;
  MeshBuilder(mesh).AddBox({3, -2, 1}, {1.5, 0.5, 2.0}, 0.7, Material::kBrick);
  EXPECT_EQ(mesh.triangle_count(), 12u);
  EXPECT_NEAR(SignedVolume(mesh), 3.0 * 1.0 * 4.0, 1e-4);
  // The top face is at z = 3 and faces up.
  int up = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (Normal(mesh, t).normalized().z() > 0.99) ++up;
  }
  EXPECT_EQ(up, 2);
}

TEST(MeshBuilder, CylinderMatchesPrismVolume) {
  TriangleMesh mesh;
  const int sides = 9;
  const double r = 0.7, h = 2.5;
  MeshBuilder(mesh).AddCylinder({1, 2, -1}, r, h, sides, Material::kMetal);
  EXPECT_EQ(mesh.triangle_count(), 4u * sides);
  // Regular n-gon area (n / 2) r^2 sin(2 pi / n) times the height.
  const double prism = 0.5 * sides * r * r * std::sin(2.0 * std::numbers::pi / sides) * h;
  EXPECT_NEAR(SignedVolume(mesh), prism, 1e-4);
}

TEST(MeshBuilder, ConeMatchesPyramidVolume) {
  TriangleMesh mesh;
  const int sides = 7;
  MeshBuilder(mesh).AddCone({0, 0, 1}, 1.2, 3.0, sides, Material::kFoliage);
  EXPECT_EQ(mesh.triangle_count(), 2u * sides);
  const double base = 0.5 * sides * 1.2 * 1.2 * std::sin(2.0 * std::numbers::pi / sides);
  EXPECT_NEAR(SignedVolume(mesh), base * 3.0 / 3.0, 1e-4);
}

TEST(MeshBuilder, BlobIsClosedOutwardAndNearTheEllipsoid) {
  TriangleMesh mesh;
  const Eigen::Vector3d radii(2.0, 1.0, 0.5);
  MeshBuilder(mesh).AddBlob({5, 5, 5}, radii, 3, 0.0, 1, Material::kRock);
  EXPECT_EQ(mesh.triangle_count(), 20u * 64u);
  // Inscribed polyhedron: a little below the ellipsoid volume 4/3 pi abc.
  const double ellipsoid = 4.0 / 3.0 * std::numbers::pi * radii.prod();
  EXPECT_GT(SignedVolume(mesh), 0.95 * ellipsoid);
  EXPECT_LT(SignedVolume(mesh), ellipsoid);
  TriangleMesh rough;
  MeshBuilder(rough).AddBlob({0, 0, 0}, radii, 2, 0.3, 7, Material::kRock);
  EXPECT_GT(SignedVolume(rough), 0.3 * ellipsoid);
}

TEST(MeshBuilder, HeightfieldCountsSkipsAndFacesUp) {
  TriangleMesh mesh;
  const int nx = 4, ny = 3;
  std::vector<double> heights((nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) heights[j * (nx + 1) + i] = 0.3 * i - 0.2 * j;  // a plane
  }
  std::vector<bool> keep(nx * ny, true);
  keep[5] = false;
  MeshBuilder(mesh).AddHeightfield(-1.0, 2.0, 0.5, nx, ny, heights,
                                   std::vector<Material>(nx * ny, Material::kGrass), keep);
  EXPECT_EQ(mesh.triangle_count(), 2u * (nx * ny - 1));
  // Plane normal of z = 0.6 x - 0.4 y (slopes per metre with 0.5 m cells) is (-0.6, 0.4, 1).
  const Eigen::Vector3d expected = Eigen::Vector3d(-0.6, 0.4, 1.0).normalized();
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_NEAR(Normal(mesh, t).normalized().dot(expected), 1.0, 1e-6);
  }
}

TEST(MeshBuilder, SweptClosedProfileFacesInwards) {
  // A closed rectangular profile (floor left->right, right wall up, ceiling, left wall down) swept along a
  // straight line: every face normal points towards the tube's axis.
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> path = {{0, 0, 0}, {4, 0, 0}, {8, 0, 0}};
  MeshBuilder(mesh).AddSweptProfile(
      path, {{1, 0}, {-1, 0}, {-1, 2}, {1, 2}},
      {Material::kConcrete, Material::kPlaster, Material::kConcrete, Material::kPlaster}, true);
  EXPECT_EQ(mesh.triangle_count(), 2u * 4u * 2u);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3d centroid =
        (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]).cast<double>() / 3.0;
    const Eigen::Vector3d to_axis = Eigen::Vector3d(centroid.x(), 0, 1) - centroid;
    EXPECT_GT(Normal(mesh, t).dot(to_axis), 0.0) << "triangle " << t;
  }
  // Walls at left = +1 (y = +1 for a path along +x) and right = -1.
  for (const Eigen::Vector3f& v : mesh.vertices) EXPECT_NEAR(std::abs(v.y()), 1.0, 1e-6);
}

TEST(MeshBuilder, SweptProfileKeepsWallDistanceAroundABend) {
  // A 90-degree corner: the miter keeps the offset walls at distance 1 from both legs.
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> path = {{0, 0, 0}, {5, 0, 0}, {5, 5, 0}};
  MeshBuilder(mesh).AddSweptProfile(path, {{1, 0}, {-1, 0}}, {Material::kAsphalt});
  ASSERT_EQ(mesh.vertices.size(), 6u);
  EXPECT_NEAR((mesh.vertices[2] - Eigen::Vector3f(4, 1, 0)).norm(), 0.0, 1e-5);   // inner corner
  EXPECT_NEAR((mesh.vertices[3] - Eigen::Vector3f(6, -1, 0)).norm(), 0.0, 1e-5);  // outer corner
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) EXPECT_GT(Normal(mesh, t).z(), 0.0);
}

}  // namespace
}  // namespace uf::sim
