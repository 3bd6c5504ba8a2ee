#include "odometry/sim/scene/mesh_builder.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "odometry/sim/scene/lattice_noise.h"

namespace uf::sim {

MeshBuilder::MeshBuilder(TriangleMesh& mesh) : mesh_(mesh) {}

int MeshBuilder::AddVertex(const Eigen::Vector3d& p) {
  mesh_.vertices.push_back(p.cast<float>());
  return static_cast<int>(mesh_.vertices.size()) - 1;
}

void MeshBuilder::AddIndexedTriangle(int a, int b, int c, Material material) {
  mesh_.triangles.emplace_back(a, b, c);
  mesh_.materials.push_back(material);
}

void MeshBuilder::AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                              Material material) {
  const int ia = AddVertex(a), ib = AddVertex(b), ic = AddVertex(c);
  AddIndexedTriangle(ia, ib, ic, material);
}

void MeshBuilder::AddQuad(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                          const Eigen::Vector3d& p3, Material material) {
  const int i0 = AddVertex(p0), i1 = AddVertex(p1), i2 = AddVertex(p2), i3 = AddVertex(p3);
  AddIndexedTriangle(i0, i1, i2, material);
  AddIndexedTriangle(i0, i2, i3, material);
}

void MeshBuilder::AddBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half_extents, double yaw,
                         Material material) {
  // Corner k has local signs (x, y, z) = bits (0, 1, 2) of k; world = center + Rz(yaw) * local.
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::array<int, 8> v{};
  for (int k = 0; k < 8; ++k) {
    const double x = (k & 1 ? 1.0 : -1.0) * half_extents.x();
    const double y = (k & 2 ? 1.0 : -1.0) * half_extents.y();
    const double z = (k & 4 ? 1.0 : -1.0) * half_extents.z();
    v[k] = AddVertex(center + Eigen::Vector3d(c * x - s * y, s * x + c * y, z));
  }
  // Faces as corner quads, counter-clockwise seen from outside.
  constexpr int kFaces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : kFaces) {
    AddIndexedTriangle(v[f[0]], v[f[1]], v[f[2]], material);
    AddIndexedTriangle(v[f[0]], v[f[2]], v[f[3]], material);
  }
}

void MeshBuilder::AddCylinder(const Eigen::Vector3d& base_center, double radius, double height, int sides,
                              Material material) {
  assert(sides >= 3);
  const Eigen::Vector3d top_center = base_center + Eigen::Vector3d(0, 0, height);
  const int cb = AddVertex(base_center), ct = AddVertex(top_center);
  const int first = static_cast<int>(mesh_.vertices.size());
  for (int k = 0; k < sides; ++k) {
    const double a = 2.0 * std::numbers::pi * k / sides;
    const Eigen::Vector3d r(radius * std::cos(a), radius * std::sin(a), 0.0);
    AddVertex(base_center + r);
    AddVertex(top_center + r);
  }
  for (int k = 0; k < sides; ++k) {
    const int b0 = first + 2 * k, t0 = b0 + 1;
    const int b1 = first + 2 * ((k + 1) % sides), t1 = b1 + 1;
    AddIndexedTriangle(b0, b1, t1, material);  // side, counter-clockwise from outside
    AddIndexedTriangle(b0, t1, t0, material);
    AddIndexedTriangle(ct, t0, t1, material);  // top cap faces +z
    AddIndexedTriangle(cb, b1, b0, material);  // bottom cap faces -z
  }
}

void MeshBuilder::AddCone(const Eigen::Vector3d& base_center, double radius, double height, int sides,
                          Material material) {
  assert(sides >= 3);
  const int cb = AddVertex(base_center), apex = AddVertex(base_center + Eigen::Vector3d(0, 0, height));
  const int first = static_cast<int>(mesh_.vertices.size());
  for (int k = 0; k < sides; ++k) {
    const double a = 2.0 * std::numbers::pi * k / sides;
    AddVertex(base_center + Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), 0.0));
  }
  for (int k = 0; k < sides; ++k) {
    const int b0 = first + k, b1 = first + (k + 1) % sides;
    AddIndexedTriangle(b0, b1, apex, material);
    AddIndexedTriangle(cb, b1, b0, material);
  }
}

void MeshBuilder::AddBlob(const Eigen::Vector3d& center, const Eigen::Vector3d& radii, int subdivisions,
                          double roughness, std::uint64_t seed, Material material) {
  assert(subdivisions >= 0 && roughness >= 0.0 && roughness < 0.5);
  // Icosahedron: vertices (0, +-1, +-t), (+-1, +-t, 0), (+-t, 0, +-1) with t the golden ratio, on the unit
  // sphere after normalisation; faces counter-clockwise from outside.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  // Loop subdivision without smoothing: split each edge at its midpoint (pushed to the sphere).
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const int index = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces = std::move(next);
  }
  const int first = static_cast<int>(mesh_.vertices.size());
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double bump = 1.0 + roughness * (2.0 * noise::CellValue(static_cast<std::int64_t>(seed),
                                                                  static_cast<std::int64_t>(k), 0xB10Bu) -
                                           1.0);
    AddVertex(center + bump * radii.cwiseProduct(v[k]));
  }
  for (const auto& f : faces) AddIndexedTriangle(first + f[0], first + f[1], first + f[2], material);
}

void MeshBuilder::AddHeightfield(double x0, double y0, double cell, int nx, int ny,
                                 const std::vector<double>& heights,
                                 const std::vector<Material>& cell_materials,
                                 const std::vector<bool>& keep_cell) {
  assert(nx >= 1 && ny >= 1 && cell > 0.0);
  assert(heights.size() == static_cast<std::size_t>((nx + 1) * (ny + 1)));
  assert(cell_materials.size() == static_cast<std::size_t>(nx * ny));
  assert(keep_cell.empty() || keep_cell.size() == cell_materials.size());
  const int first = static_cast<int>(mesh_.vertices.size());
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) AddVertex({x0 + i * cell, y0 + j * cell, heights[j * (nx + 1) + i]});
  }
  // Cell corners a = (i, j), b = (i + 1, j), c = (i + 1, j + 1), d = (i, j + 1): counter-clockwise from
  // above (+z), so the triangles face up.
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int c_index = j * nx + i;
      if (!keep_cell.empty() && !keep_cell[c_index]) continue;
      const int a = first + j * (nx + 1) + i, b = a + 1, d = a + nx + 1, c = d + 1;
      AddIndexedTriangle(a, b, c, cell_materials[c_index]);
      AddIndexedTriangle(a, c, d, cell_materials[c_index]);
    }
  }
}

void MeshBuilder::AddSweptProfile(const std::vector<Eigen::Vector3d>& path,
                                  const std::vector<Eigen::Vector2d>& profile,
                                  const std::vector<Material>& edge_materials, bool closed) {
  assert(path.size() >= 2 && profile.size() >= 2);
  const std::size_t edges = closed ? profile.size() : profile.size() - 1;
  assert(edge_materials.size() == edges);
  const std::size_t n = path.size(), m = profile.size();
  const int first = static_cast<int>(mesh_.vertices.size());
  for (std::size_t i = 0; i < n; ++i) {
    // Horizontal unit directions of the incoming and outgoing segments; left = z x bisector, scaled by the
    // miter factor 1 / cos(half turn) = 1 / (left . left_of_segment).
    auto direction = [&](std::size_t a, std::size_t b) {
      Eigen::Vector2d d = (path[b] - path[a]).head<2>();
      const double norm = d.norm();
      return norm > 1e-9 ? Eigen::Vector2d(d / norm) : Eigen::Vector2d(1.0, 0.0);
    };
    const Eigen::Vector2d d_in = i > 0 ? direction(i - 1, i) : direction(0, 1);
    const Eigen::Vector2d d_out = i + 1 < n ? direction(i, i + 1) : direction(n - 2, n - 1);
    Eigen::Vector2d bisector = d_in + d_out;
    if (bisector.norm() < 1e-9) bisector = d_out;
    bisector.normalize();
    const Eigen::Vector2d left2(-bisector.y(), bisector.x());
    const double cos_half = std::max(0.5, left2.dot(Eigen::Vector2d(-d_out.y(), d_out.x())));
    const Eigen::Vector3d left(left2.x() / cos_half, left2.y() / cos_half, 0.0);
    for (std::size_t k = 0; k < m; ++k) {
      AddVertex(path[i] + profile[k].x() * left + Eigen::Vector3d(0, 0, profile[k].y()));
    }
  }
  // Quad between path points i, i + 1 and profile points k, k + 1: A = (i, k), B = (i, k + 1),
  // C = (i + 1, k + 1), D = (i + 1, k); its normal (B - A) x (C - A) ~ e x forward = (b, -a) in (left, up).
  for (std::size_t i = 0; i + 1 < n; ++i) {
    for (std::size_t k = 0; k < edges; ++k) {
      const std::size_t k1 = (k + 1) % m;
      const int a = first + static_cast<int>(i * m + k), b = first + static_cast<int>(i * m + k1);
      const int c = first + static_cast<int>((i + 1) * m + k1), d = first + static_cast<int>((i + 1) * m + k);
      AddIndexedTriangle(a, b, c, edge_materials[k]);
      AddIndexedTriangle(a, c, d, edge_materials[k]);
    }
  }
}

double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t[2]].cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

}  // namespace uf::sim
