// A triangle mesh with per-vertex colours, as meshing produces it and the glTF writer consumes it.
// Vertex positions are double precision in the map frame, like MapPoint.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace uf::mapping {

struct ColoredMesh {
  std::vector<Eigen::Vector3d> vertices;                  // map frame, m
  std::vector<std::array<std::uint8_t, 3>> colors;        // sRGB, one per vertex (grey where uncoloured)
  std::vector<Eigen::Vector3f> normals;                   // unit, one per vertex, or empty
  std::vector<std::array<std::uint32_t, 3>> triangles;    // counter-clockwise seen from outside

  bool empty() const { return triangles.empty(); }
};

}  // namespace uf::mapping
