// A read-only view of a GlobalMap for later stages (exports, meshing, splat seeding): the voxels that pass
// the noise filter (GlobalMapConfig::min_observations, min_neighbors_if_unconfirmed), as MapPoints,
// delivered chunk by chunk in the grid's leaf-node order (spatially coherent tiles of 8^3 voxels), so a
// writer streams a map of any size while holding one chunk. Also nearest-point and radius queries.
//
// Normals are estimated when points are delivered: PCA of the representative points of all occupied voxels
// in the (2r+1)^3 neighbourhood (r = normal_radius_voxels); the normal is the eigenvector of the smallest
// eigenvalue of their covariance, flipped to face the mean direction towards the sensor. A neighbourhood
// with fewer than 3 points, or that is not planar enough to define a normal (middle eigenvalue less than
// 3x the smallest, e.g. a single scan line) gives a zero normal ("unknown").
//
// The view refers to the map: it must not outlive it, and is invalid (asserts) once the map changes.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "mapping/global_map.h"
#include "mapping/point_source.h"

namespace uf::mapping {

struct MapViewOptions {
  std::size_t chunk_size = 65536;  // points per chunk delivered by ForEachChunk (> 0)
  // false: normals stay zero (faster export). Normals are computed on the first pass over the view and
  // cached (12 bytes per voxel), so writers that read the view several times pay for them once.
  bool compute_normals = true;
};

class MapView final : public PointSource {
 public:
  explicit MapView(const GlobalMap& map, MapViewOptions options = {});

  std::size_t size() const override { return size_; }
  Eigen::AlignedBox3d bounds() const override { return bounds_; }
  bool ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const override;

  // The visible point nearest to `query` within max_distance_m (optionally only coloured points), or none.
  std::optional<MapPoint> Nearest(const Eigen::Vector3d& query, double max_distance_m,
                                  bool require_color = false) const;
  // All visible points within radius_m of `centre`, in no particular order.
  std::vector<MapPoint> RadiusSearch(const Eigen::Vector3d& centre, double radius_m) const;

  const GlobalMap& map() const { return *map_; }

 private:
  MapPoint PointOf(std::size_t voxel) const;

  const GlobalMap* map_;
  MapViewOptions options_;
  std::uint64_t revision_;
  std::vector<bool> visible_;                     // per voxel index of the map
  mutable std::vector<Eigen::Vector3f> normals_;  // per voxel index; NaN until computed
  std::size_t size_ = 0;
  Eigen::AlignedBox3d bounds_;
};

}  // namespace uf::mapping
