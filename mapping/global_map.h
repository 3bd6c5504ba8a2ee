// The global map: a sparse voxel grid (OpenVDB, kept out of this header) fed with world-frame scans. Each
// occupied voxel keeps one representative point (the running mean of the points that fell into it), an
// outlier-robust running mean colour, the mean intensity, the observation count, the last observation time
// and the mean direction towards the sensor (to orient normals). Memory is bounded by max_voxels.
//
// Voxels: voxel (i, j, k) is centred at (i, j, k) * voxel_size_m (OpenVDB's cell-centred convention) and
// covers [c - s/2, c + s/2) per axis, so a point p falls into ijk = floor(p / s + 1/2). The representative
// point is stored as the voxel centre (exact, from the integer index) plus a float offset, so positions keep
// sub-millimetre precision however far the map is from its origin.
//
// Read the map through MapView (map_view.h); save and load it with map_file.h.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "odometry/types/keyframe.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::mapping {

// An sRGB colour of one point, or none (the point was outside every camera image or occluded).
using PointColor = std::optional<std::array<std::uint8_t, 3>>;

struct GlobalMapConfig {
  double voxel_size_m = 0.05;  // edge of a voxel, in [0.001, 100] m
  // At most this many voxels (in [1, 2^31 - 1]); ~80 bytes each plus the grid, so the default is ~1.7 GB.
  // When a new voxel would exceed it, the map evicts down to 90 % of it: the voxels whose last observation
  // is oldest go first, and among equally old ones those farthest from the latest sensor origin (so within
  // one scan the far, sparse returns go before the near ones).
  std::size_t max_voxels = 20'000'000;
  // A voxel appears in MapView once it has this many points (>= 1): a single return is likely noise (dust,
  // a passing car, a mixed pixel at an edge) ...
  int min_observations = 2;
  // ... unless it is supported by at least this many occupied voxels among its 26 neighbours (in [0, 27];
  // 27 disables the exception). At 5 cm voxels a far wall is hit about once per voxel and scan, yet lies on
  // a continuous scan line; an isolated noise return has no neighbours.
  int min_neighbors_if_unconfirmed = 2;
  // Colour outlier rejection (colours in sRGB units 0..255, distances Euclidean over the three channels).
  // Once a voxel has color_min_samples accepted colours, a new colour farther than
  // color_outlier_sigma * max(sigma, color_sigma_floor) from the running mean is rejected, sigma being the
  // RMS distance of the accepted colours from their mean. A wrong colour is a gross error (the projection
  // hit the wrong surface at an occlusion edge, a moving object, a calibration error), not Gaussian noise,
  // so a k-sigma gate removes it while the floor keeps exposure changes between frames from being rejected
  // in voxels whose first colours happened to agree exactly.
  int color_min_samples = 3;         // >= 2
  double color_outlier_sigma = 3.0;  // > 0
  double color_sigma_floor = 20.0;   // >= 0, sRGB units
  // MapView estimates normals from the representative points of the voxels within this many voxels (a
  // (2r+1)^3 cube), in [1, 4].
  int normal_radius_voxels = 2;

  // Ok, or an error naming the field and its value ("map.voxel_size_m: must be in [0.001, 100], got -1").
  Status Validate() const;
};

struct GlobalMapStats {
  std::size_t voxels = 0;                    // occupied voxels now
  std::uint64_t points_inserted = 0;         // points merged into voxels
  std::uint64_t points_skipped_invalid = 0;  // NaN / Inf coordinates, or beyond the grid's index range
  std::uint64_t colors_rejected = 0;         // colour samples rejected as outliers
  std::uint64_t voxels_evicted = 0;          // voxels dropped to stay within max_voxels
  std::size_t memory_bytes = 0;              // voxel attributes + grid, approximate
};

// One scan to insert: points in the world (map) frame, optional per-point intensity and colour.
struct WorldScan {
  Stamp stamp = 0;                                                // becomes the voxels' last_stamp
  Eigen::Vector3d sensor_origin_world = Eigen::Vector3d::Zero();  // where the sensor was (orients normals)
  std::span<const Eigen::Vector3f> points;                        // world frame, m
  std::span<const float> intensity;                               // empty (all 0) or one per point
  std::span<const PointColor> colors;                             // empty (uncoloured) or one per point
};

class GlobalMap {
 public:
  // Fails with the config's validation error.
  static Expected<GlobalMap> Create(const GlobalMapConfig& config);

  GlobalMap(GlobalMap&&) noexcept;
  GlobalMap& operator=(GlobalMap&&) noexcept;
  ~GlobalMap();

  // Merges the scan's points. NaN / Inf points are skipped and counted. Fails, inserting nothing, when
  // intensity or colors is neither empty nor one per point.
  Status Insert(const WorldScan& scan);
  // A keyframe's deskewed scan, with the body origin standing in for the sensor origin; colors as above.
  Status Insert(const Keyframe& keyframe, std::span<const PointColor> colors = {});

  const GlobalMapConfig& config() const;
  GlobalMapStats stats() const;
  std::size_t size() const;  // occupied voxels
  // Incremented by every change; a MapView is valid only while the map's revision is the one it saw.
  std::uint64_t revision() const;

  struct Impl;  // defined in global_map_impl.h (OpenVDB), used by map_view, map_file and meshing

 private:
  friend struct GlobalMapAccess;
  explicit GlobalMap(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::mapping
