// MeshFromMap on sampled analytic surfaces: a closed sphere and an open plane patch. Vertices must lie within
// one voxel of the analytic surface, the mesh must cover it (area), triangles must wind counter-clockwise
// seen from outside, and vertex colours must come from the nearby coloured points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mapping/meshing.h"
#include "mapping/point_source.h"

namespace uf::mapping {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

double Area(const ColoredMesh& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles)
    area +=
        0.5 *
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  return area;
}

// Fibonacci sphere: about one point per voxel of area, outward normals, red above the equator, blue below.
TEST(Meshing, SphereVerticesLieOnTheSurface) {
  const Eigen::Vector3d centre(1000.0, -2000.0, 30.0);  // far from the origin on purpose
  const double radius = 1.0, voxel = 0.05;
  const int n = static_cast<int>(4 * M_PI * radius * radius / (voxel * voxel));
  std::vector<MapPoint> points;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), phi = golden * i;
    const Eigen::Vector3d u(r * std::cos(phi), r * std::sin(phi), z);
    MapPoint p;
    p.position = centre + radius * u;
    p.normal = u.cast<float>();
    p.has_color = true;
    p.rgb = z > 0 ? Rgb{255, 0, 0} : Rgb{0, 0, 255};
    points.push_back(p);
  }
  MeshOptions options;
  options.voxel_size_m = voxel;
  const auto mesh = MeshFromMap(VectorPointSource(points, 1000), options);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  ASSERT_FALSE(mesh->empty());
  ASSERT_EQ(mesh->colors.size(), mesh->vertices.size());
  ASSERT_EQ(mesh->normals.size(), mesh->vertices.size());
  double worst = 0;
  for (std::size_t i = 0; i < mesh->vertices.size(); ++i) {
    const Eigen::Vector3d d = mesh->vertices[i] - centre;
    worst = std::max(worst, std::abs(d.norm() - radius));
    if (std::abs(d.z()) > 0.1) {
      EXPECT_EQ(mesh->colors[i], d.z() > 0 ? (Rgb{255, 0, 0}) : (Rgb{0, 0, 255}));
    }
  }
  EXPECT_LT(worst, voxel);
  EXPECT_NEAR(Area(*mesh), 4 * M_PI * radius * radius, 0.05 * 4 * M_PI * radius * radius);
  // Winding: the face normal (b - a) x (c - a) points away from the centre.
  std::size_t outward = 0;
  for (const auto& t : mesh->triangles) {
    const Eigen::Vector3d& a = mesh->vertices[t[0]];
    const Eigen::Vector3d face = (mesh->vertices[t[1]] - a).cross(mesh->vertices[t[2]] - a);
    outward += face.dot(a - centre) > 0 ? 1 : 0;
  }
  EXPECT_GE(static_cast<double>(outward), 0.999 * static_cast<double>(mesh->triangles.size()));
}

// An open 2 m x 2 m patch of z = 0 with jittered samples: one sheet, no wall at the band's rim.
TEST(Meshing, OpenPlaneGivesOneSheet) {
  const double voxel = 0.05;
  std::mt19937_64 engine(5);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  std::vector<MapPoint> points;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) {
      MapPoint p;
      const double x = 0.05 * i + jitter(engine), y = 0.05 * j + jitter(engine), z = 0.3 * jitter(engine);
      p.position = Eigen::Vector3d(x, y, z);
      p.normal = Eigen::Vector3f::UnitZ();
      points.push_back(p);
    }
  MeshOptions options;
  options.voxel_size_m = voxel;
  const auto mesh = MeshFromMap(VectorPointSource(points), options);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  ASSERT_FALSE(mesh->empty());
  for (std::size_t i = 0; i < mesh->vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh->vertices[i];
    EXPECT_LT(std::abs(v.z()), voxel);
    EXPECT_LT(v.head<2>().cwiseAbs().maxCoeff(), 1.0 + 2 * voxel);
    EXPECT_EQ(mesh->colors[i], (Rgb{128, 128, 128}));  // no coloured points: grey
  }
  // One sheet over (most of) the 2 x 2 patch, not two.
  EXPECT_GT(Area(*mesh), 0.85 * 4.0);
  EXPECT_LT(Area(*mesh), 1.15 * 4.0);
  for (const auto& t : mesh->triangles) {
    const Eigen::Vector3d face =
        (mesh->vertices[t[1]] - mesh->vertices[t[0]]).cross(mesh->vertices[t[2]] - mesh->vertices[t[0]]);
    EXPECT_GT(face.z(), 0.0);  // counter-clockwise seen from +z, where the normals point
  }
}

TEST(Meshing, BadOptionsAndEmptyInput) {
  MeshOptions options;
  options.band_voxels = 0;
  const auto bad = MeshFromMap(VectorPointSource({}), options);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("mesh.band_voxels"), std::string::npos);
  const auto empty = MeshFromMap(VectorPointSource({}), MeshOptions{});
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
  // Points without normals give no surface.
  MapPoint p;
  p.position = Eigen::Vector3d(1, 2, 3);
  const auto no_normals = MeshFromMap(VectorPointSource({p, p}), MeshOptions{});
  ASSERT_TRUE(no_normals.ok());
  EXPECT_TRUE(no_normals->empty());
}

}  // namespace
}  // namespace uf::mapping
