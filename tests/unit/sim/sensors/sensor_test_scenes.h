// Hand-built scenes for the sensor tests (plain TriangleMesh geometry, independent of the scene builders) and
// a brute-force point-to-mesh distance used as the independent truth for where returns must lie.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>

#include "odometry/sim/scene/scene.h"
#include "tests/support/triangle_distance.h"

namespace uf::sim::test {

using uf::testing::PointTriangleDistance;

// Appends an axis-aligned box [lo, hi] as 12 triangles (two per face) of one material.
inline void AddBox(TriangleMesh& mesh, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                   Material material) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i) {  // corner i: bit 0 -> x, bit 1 -> y, bit 2 -> z
    mesh.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                               (i & 4) ? hi.z() : lo.z());
  }
  // Faces as corner quads, counter-clockwise seen from outside the box.
  const std::array<std::array<int, 4>, 6> faces = {{
      {0, 2, 3, 1},
      {4, 5, 7, 6},  // z = lo, z = hi
      {0, 1, 5, 4},
      {2, 6, 7, 3},  // y = lo, y = hi
      {0, 4, 6, 2},
      {1, 3, 7, 5},  // x = lo, x = hi
  }};
  for (const auto& f : faces) {
    mesh.triangles.emplace_back(base + f[0], base + f[1], base + f[2]);
    mesh.triangles.emplace_back(base + f[0], base + f[2], base + f[3]);
    mesh.materials.push_back(material);
    mesh.materials.push_back(material);
  }
}

// Appends the rectangle {x = x0} x [y0, y1] x [z0, z1] (a wall facing +-x) as two triangles.
inline void AddWallX(TriangleMesh& mesh, float x0, float y0, float y1, float z0, float z1,
                     Material material) {
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(x0, y0, z0);
  mesh.vertices.emplace_back(x0, y1, z0);
  mesh.vertices.emplace_back(x0, y1, z1);
  mesh.vertices.emplace_back(x0, y0, z1);
  mesh.triangles.emplace_back(base, base + 1, base + 2);
  mesh.triangles.emplace_back(base, base + 2, base + 3);
  mesh.materials.insert(mesh.materials.end(), 2, material);
}

// A closed room 40 x 30 x 8 m around the origin (floor at z = -2) with a few boxes inside: every ray from
// inside hits something within 60 m.
inline Scene BoxRoomScene() {
  Scene scene;
  scene.name = "box_room";
  AddBox(scene.mesh, {-20, -15, -2}, {20, 15, 6}, Material::kConcrete);
  AddBox(scene.mesh, {5, 2, -2}, {7, 4, 1}, Material::kCardboard);
  AddBox(scene.mesh, {-8, -6, -2}, {-6, -3, 3}, Material::kBrick);
  AddBox(scene.mesh, {2, -9, -2}, {3, -8, 4}, Material::kMetal);
  AddBox(scene.mesh, {-12, 6, -1}, {-9, 9, 0.5f}, Material::kCarPaint);
  return scene;
}

// Distance from p to the nearest triangle of the mesh, by brute force.
inline double DistanceToMesh(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3i& t : mesh.triangles) {
    best = std::min(
        best, PointTriangleDistance(p, mesh.vertices[t[0]].cast<double>(), mesh.vertices[t[1]].cast<double>(),
                                    mesh.vertices[t[2]].cast<double>()));
  }
  return best;
}

}  // namespace uf::sim::test
