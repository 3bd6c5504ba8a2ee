#include <algorithm>
#include <cmath>

#include "odometry/sim/scene/mesh_builder.h"
#include "odometry/sim/scene/scene_generators.h"

namespace uf::sim {

void AddGround(const ScenePath& path, double margin, double keep_within, double cell, double skip_within,
               const std::function<double(double x, double y, double d)>& relief,
               const std::function<Material(double x, double y, double d, double slope)>& material,
               TriangleMesh& mesh) {
  const Eigen::Vector2d lo = path.min_xy() - Eigen::Vector2d::Constant(margin);
  const Eigen::Vector2d extent = path.max_xy() - path.min_xy() + Eigen::Vector2d::Constant(2.0 * margin);
  constexpr double kMaxCells = 3e5;
  cell = std::max(cell, std::sqrt(extent.x() * extent.y() / kMaxCells));
  const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / cell)));
  const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / cell)));
  std::vector<double> heights((nx + 1) * (ny + 1)), distance((nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = lo.x() + i * cell, y = lo.y() + j * cell;
      const ScenePath::Nearest nearest = path.NearestPoint(x, y);
      const int k = j * (nx + 1) + i;
      distance[k] = nearest.distance;
      heights[k] = nearest.z - path.body_height() + relief(x, y, nearest.distance);
    }
  }
  std::vector<Material> materials(nx * ny);
  std::vector<bool> keep(nx * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, d = a + nx + 1, c = d + 1;
      const double d_min = std::min({distance[a], distance[b], distance[c], distance[d]});
      const double d_max = std::max({distance[a], distance[b], distance[c], distance[d]});
      keep[j * nx + i] = d_min <= keep_within && !(skip_within > 0.0 && d_max < skip_within);
      // Slope from the cell's central differences: |grad h| with dh/dx, dh/dy averaged over the two rows.
      const double gx = 0.5 * (heights[b] - heights[a] + heights[c] - heights[d]) / cell;
      const double gy = 0.5 * (heights[d] - heights[a] + heights[c] - heights[b]) / cell;
      materials[j * nx + i] = material(lo.x() + (i + 0.5) * cell, lo.y() + (j + 0.5) * cell,
                                       0.5 * (d_min + d_max), std::hypot(gx, gy));
    }
  }
  MeshBuilder(mesh).AddHeightfield(lo.x(), lo.y(), cell, nx, ny, heights, materials, keep);
}

}  // namespace uf::sim
