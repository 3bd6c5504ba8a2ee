#include "mapping/map_view.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "mapping/global_map_impl.h"

namespace uf::mapping {
namespace {

using Accessor = openvdb::Int32Grid::ConstAccessor;

// Occupied voxels among the 27 of the 3x3x3 block around ijk (ijk itself included).
int OccupiedAround(const Accessor& accessor, const openvdb::Coord& ijk) {
  int occupied = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) occupied += accessor.isValueOn(ijk.offsetBy(dx, dy, dz)) ? 1 : 0;
  return occupied;
}

// PCA normal (see map_view.h), positions taken relative to the voxel's own point for precision:
// C = sum (q - m)(q - m)^T over the neighbours q, m their mean; n = eigenvector of C's smallest eigenvalue.
Eigen::Vector3f EstimateNormal(const GlobalMap::Impl& map, const Accessor& accessor, const VoxelData& voxel) {
  const int r = map.config.normal_radius_voxels;
  const Eigen::Vector3d origin = map.Position(voxel);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int count = 0;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy)
      for (int dz = -r; dz <= r; ++dz) {
        std::int32_t slot = -1;
        if (!accessor.probeValue(voxel.ijk.offsetBy(dx, dy, dz), slot)) continue;
        const Eigen::Vector3d q = map.Position(map.voxels[static_cast<std::size_t>(slot)]) - origin;
        sum += q;
        outer += q * q.transpose();
        ++count;
      }
  if (count < 3) return Eigen::Vector3f::Zero();
  const Eigen::Vector3d mean = sum / count;
  const Eigen::Matrix3d covariance = outer / count - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  const Eigen::Vector3d lambda = solver.eigenvalues();  // ascending
  // A plane needs a second direction of real extent: lambda_1 > 3 lambda_0 and above (1 % of a voxel)^2.
  const double tiny = 1e-4 * map.config.voxel_size_m * map.config.voxel_size_m;
  if (!(lambda(1) > 3.0 * lambda(0) && lambda(1) > tiny)) return Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = solver.eigenvectors().col(0).cast<float>().normalized();
  if (normal.dot(voxel.view_sum) < 0) normal = -normal;  // face the sensor
  return normal;
}

}  // namespace

MapView::MapView(const GlobalMap& map, MapViewOptions options)
    : map_(&map), options_(options), revision_(map.revision()) {
  assert(options_.chunk_size > 0);
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(map);
  const GlobalMapConfig& config = impl.config;
  const auto min_count = static_cast<std::uint32_t>(config.min_observations);
  Accessor accessor = impl.index->getConstAccessor();
  visible_.assign(impl.voxels.size(), false);
  for (std::size_t i = 0; i < impl.voxels.size(); ++i) {
    const VoxelData& v = impl.voxels[i];
    // Confirmed by enough points, or supported by occupied neighbours (the voxel itself excluded).
    const bool visible =
        v.count >= min_count || (config.min_neighbors_if_unconfirmed < 27 &&
                                 OccupiedAround(accessor, v.ijk) - 1 >= config.min_neighbors_if_unconfirmed);
    if (!visible) continue;
    visible_[i] = true;
    ++size_;
    bounds_.extend(impl.Position(v));
  }
}

MapPoint MapView::PointOf(std::size_t voxel) const {
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(*map_);
  const VoxelData& v = impl.voxels[voxel];
  MapPoint point;
  point.position = impl.Position(v);
  point.intensity = v.intensity_mean;
  point.count = v.count;
  point.last_stamp = v.last_stamp;
  point.has_color = v.color_count > 0;
  if (point.has_color)
    for (int c = 0; c < 3; ++c)
      point.rgb[static_cast<std::size_t>(c)] =
          static_cast<std::uint8_t>(std::clamp(std::lround(v.color_mean(c)), 0L, 255L));
  return point;
}

bool MapView::ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const {
  assert(map_->revision() == revision_ && "MapView used after its map changed");
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(*map_);
  std::vector<std::size_t> voxels;
  std::vector<MapPoint> buffer;
  voxels.reserve(std::min(options_.chunk_size, size_));
  if (options_.compute_normals && normals_.empty())
    normals_.assign(impl.voxels.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  // Fills and delivers the chunk of the collected voxels; each point is independent, so the normals are
  // computed in parallel with the same result as serially.
  const auto deliver = [&] {
    buffer.resize(voxels.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 1024), [&](const auto& range) {
      Accessor accessor = impl.index->getConstAccessor();
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        buffer[i] = PointOf(voxels[i]);
        if (!options_.compute_normals) continue;
        Eigen::Vector3f& normal = normals_[voxels[i]];  // distinct voxels: no two threads share one
        if (std::isnan(normal.x())) normal = EstimateNormal(impl, accessor, impl.voxels[voxels[i]]);
        buffer[i].normal = normal;
      }
    });
    voxels.clear();
    return chunk(buffer);
  };
  // Leaf by leaf (8^3-voxel tiles, in the tree's deterministic order), voxel by voxel inside a leaf.
  for (auto leaf = impl.index->tree().cbeginLeaf(); leaf; ++leaf) {
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const auto voxel = static_cast<std::size_t>(*it);
      if (!visible_[voxel]) continue;
      voxels.push_back(voxel);
      if (voxels.size() == options_.chunk_size && !deliver()) return false;
    }
  }
  return voxels.empty() || deliver();
}

std::optional<MapPoint> MapView::Nearest(const Eigen::Vector3d& query, double max_distance_m,
                                         bool require_color) const {
  assert(map_->revision() == revision_ && "MapView used after its map changed");
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(*map_);
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(max_distance_m);
  const auto low = impl.VoxelOf(query - reach), high = impl.VoxelOf(query + reach);
  if (!low || !high) return std::nullopt;
  Accessor accessor = impl.index->getConstAccessor();
  double best = max_distance_m * max_distance_m;
  std::optional<std::size_t> best_voxel;
  // A point lies in the voxel that contains it, so the voxels of [query - d, query + d] hold every candidate.
  for (int x = low->x(); x <= high->x(); ++x)
    for (int y = low->y(); y <= high->y(); ++y)
      for (int z = low->z(); z <= high->z(); ++z) {
        std::int32_t slot = -1;
        if (!accessor.probeValue(openvdb::Coord(x, y, z), slot)) continue;
        const auto voxel = static_cast<std::size_t>(slot);
        if (!visible_[voxel] || (require_color && impl.voxels[voxel].color_count == 0)) continue;
        const double d2 = (impl.Position(impl.voxels[voxel]) - query).squaredNorm();
        if (d2 <= best) best = d2, best_voxel = voxel;
      }
  if (!best_voxel) return std::nullopt;
  MapPoint point = PointOf(*best_voxel);
  if (options_.compute_normals) point.normal = EstimateNormal(impl, accessor, impl.voxels[*best_voxel]);
  return point;
}

std::vector<MapPoint> MapView::RadiusSearch(const Eigen::Vector3d& centre, double radius_m) const {
  assert(map_->revision() == revision_ && "MapView used after its map changed");
  const GlobalMap::Impl& impl = GlobalMapAccess::Of(*map_);
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(radius_m);
  const auto low = impl.VoxelOf(centre - reach), high = impl.VoxelOf(centre + reach);
  std::vector<MapPoint> found;
  if (!low || !high) return found;
  Accessor accessor = impl.index->getConstAccessor();
  for (int x = low->x(); x <= high->x(); ++x)
    for (int y = low->y(); y <= high->y(); ++y)
      for (int z = low->z(); z <= high->z(); ++z) {
        std::int32_t slot = -1;
        if (!accessor.probeValue(openvdb::Coord(x, y, z), slot)) continue;
        const auto voxel = static_cast<std::size_t>(slot);
        if (!visible_[voxel] || (impl.Position(impl.voxels[voxel]) - centre).norm() > radius_m) continue;
        MapPoint point = PointOf(voxel);
        if (options_.compute_normals) point.normal = EstimateNormal(impl, accessor, impl.voxels[voxel]);
        found.push_back(point);
      }
  return found;
}

}  // namespace uf::mapping
