// MeshBuilder: appends geometric primitives (quads, boxes, cylinders, cones, blobs, heightfields, swept
// profiles) to a TriangleMesh. Every triangle is wound counter-clockwise seen from the front (outside), so
// its normal (b - a) x (c - a) points outwards; closed primitives are watertight in that sense.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "odometry/sim/scene/scene.h"

namespace uf::sim {

class MeshBuilder {
 public:
  explicit MeshBuilder(TriangleMesh& mesh);

  void AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   Material material);

  // A planar quad p0 p1 p2 p3, counter-clockwise seen from the front: triangles (p0 p1 p2), (p0 p2 p3).
  void AddQuad(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
               const Eigen::Vector3d& p3, Material material);

  // A closed box (12 triangles) rotated by yaw (rad, about +z) around its center.
  void AddBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half_extents, double yaw,
              Material material);

  // A vertical closed cylinder (regular `sides`-gon prism, sides >= 3) standing on base_center:
  // 2 * sides side triangles + 2 * sides cap triangles (fans around the cap centres).
  void AddCylinder(const Eigen::Vector3d& base_center, double radius, double height, int sides,
                   Material material);

  // A vertical closed cone (pyramid over a regular `sides`-gon): sides mantle + sides base triangles.
  void AddCone(const Eigen::Vector3d& base_center, double radius, double height, int sides,
               Material material);

  // An ellipsoid with semi-axes `radii` from an icosahedron subdivided `subdivisions` times
  // (20 * 4^subdivisions triangles). roughness > 0 displaces each vertex radially by a factor in
  // [1 - roughness, 1 + roughness] from a hash of (seed, vertex): rocks and tree crowns. roughness < 0.5.
  void AddBlob(const Eigen::Vector3d& center, const Eigen::Vector3d& radii, int subdivisions,
               double roughness, std::uint64_t seed, Material material);

  // A terrain grid of nx * ny cells of size cell (m) starting at corner (x0, y0): heights has
  // (nx + 1) * (ny + 1) entries, heights[j * (nx + 1) + i] at (x0 + i * cell, y0 + j * cell). Cell (i, j)
  // gets material cell_materials[j * nx + i] and two triangles facing up; a cell is skipped when
  // keep_cell is non-empty and keep_cell[j * nx + i] is false.
  void AddHeightfield(double x0, double y0, double cell, int nx, int ny, const std::vector<double>& heights,
                      const std::vector<Material>& cell_materials, const std::vector<bool>& keep_cell = {});

  // Sweeps a 2D cross-section along a polyline (at least 2 points). Profile points are (left, up) offsets
  // in the frame of each path point: up = +z, left = z x (horizontal tangent), scaled by the miter factor
  // 1 / cos(half the turn angle) (capped at 2) so that walls keep their distance around bends. Profile edge
  // k (points k -> k + 1) gets edge_materials[k]; if closed, the last point connects back to the first (and
  // edge_materials has one entry per point). Normal convention: an edge with direction (a, b) in
  // (left, up) has normal (b, -a) in (left, up), e.g. a floor walked from left to right faces up, and a
  // closed profile walked floor-left-to-right, right wall up, ceiling right-to-left faces inwards.
  void AddSweptProfile(const std::vector<Eigen::Vector3d>& path, const std::vector<Eigen::Vector2d>& profile,
                       const std::vector<Material>& edge_materials, bool closed = false);

 private:
  int AddVertex(const Eigen::Vector3d& p);
  void AddIndexedTriangle(int a, int b, int c, Material material);

  TriangleMesh& mesh_;
};

// Signed volume enclosed by the mesh, (1/6) sum over triangles of a . (b x c) (divergence theorem): positive
// for a closed mesh with outward normals.
double SignedVolume(const TriangleMesh& mesh);

}  // namespace uf::sim
