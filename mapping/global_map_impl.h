// Internal to mapping/: the storage behind GlobalMap. An OpenVDB Int32Grid maps each occupied voxel to an
// index into a dense array of per-voxel attributes (the grid stores topology compactly, the array keeps the
// attributes contiguous and cheap to update). Includes OpenVDB: include it from mapping .cpp files only.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <vector>

#include "mapping/global_map.h"

namespace uf::mapping {

// Attributes of one voxel; see GlobalMap for their meaning.
struct VoxelData {
  openvdb::Coord ijk;                                     // the voxel (centre = ijk * voxel_size)
  Eigen::Vector3f offset_mean = Eigen::Vector3f::Zero();  // mean of (point - centre), m
  Eigen::Vector3f view_sum = Eigen::Vector3f::Zero();     // sum of unit vectors point -> sensor
  Eigen::Vector3f color_mean = Eigen::Vector3f::Zero();   // sRGB units 0..255, accepted samples
  float color_m2 = 0;  // Welford: sum over accepted colours of |c - mean| * |c - mean_before|
  float intensity_mean = 0;
  std::uint32_t count = 0;        // points merged
  std::uint32_t color_count = 0;  // colours accepted
  Stamp last_stamp = 0;
};

struct GlobalMap::Impl {
  GlobalMapConfig config;
  openvdb::Int32Grid::Ptr index;  // voxel -> position in `voxels`; active exactly where occupied
  std::vector<VoxelData> voxels;
  GlobalMapStats stats;
  Eigen::Vector3d latest_origin = Eigen::Vector3d::Zero();  // sensor origin of the latest scan
  std::uint64_t revision = 0;

  explicit Impl(const GlobalMapConfig& c);

  Eigen::Vector3d Centre(const openvdb::Coord& ijk) const {
    return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * config.voxel_size_m;
  }
  Eigen::Vector3d Position(const VoxelData& v) const { return Centre(v.ijk) + v.offset_mean.cast<double>(); }
  // The voxel containing p, or nullopt when p is not finite or beyond the int32 index range.
  std::optional<openvdb::Coord> VoxelOf(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d x = p / config.voxel_size_m;
    constexpr double kLimit = 1 << 30;
    if (!x.allFinite() || x.cwiseAbs().maxCoeff() >= kLimit) return std::nullopt;
    return openvdb::Coord(static_cast<int>(std::floor(x.x() + 0.5)),
                          static_cast<int>(std::floor(x.y() + 0.5)),
                          static_cast<int>(std::floor(x.z() + 0.5)));
  }
  // Drops voxels down to 90 % of max_voxels (see GlobalMapConfig::max_voxels).
  void Evict();
};

// Access to a GlobalMap's storage for mapping/ internals (view, file, meshing).
struct GlobalMapAccess {
  static const GlobalMap::Impl& Of(const GlobalMap& map) { return *map.impl_; }
  static GlobalMap Wrap(std::unique_ptr<GlobalMap::Impl> impl) { return GlobalMap(std::move(impl)); }
};

// The voxel size transform of the map's grids: index space scaled by voxel_size, voxel centres at ijk * s.
openvdb::math::Transform::Ptr VoxelTransform(double voxel_size_m);

}  // namespace uf::mapping
