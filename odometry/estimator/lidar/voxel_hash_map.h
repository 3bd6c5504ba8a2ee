// The LiDAR local map of the estimator: a voxel hash of world points (KISS-ICP style, bounded points per
// voxel and bounded range) that answers "which plane is near this world point?" for the point-to-plane
// factor.
//
// Each voxel keeps at most max_points_per_voxel points (later ones are ignored) and their moments relative
// to its centre. The plane of voxel v is the PCA plane (plane_fit.h) of the points of v and its 26
// neighbours (a 3x3x3 block of voxels, 1.5 m wide at 0.5 m voxels), moved to pass through their centroid
// weighted towards v (VoxelMapConfig::neighbour_weight), gated by lambda_min / lambda_mid and,
// optionally, by the number of distinct LiDAR rings (scan lines) among its points (min_plane_rings); a
// voxel that holds no points gets the plane of its neighbours' points the same way. Planes are fitted on
// each query from the block's moments (27 moment sums and a 3x3 eigen-decomposition), never cached: every
// scan inserts a point into most voxels in view, so a per-voxel cache would rarely survive until the next
// scan, and without one the queries are const. Callers cache per query point within one map revision
// (QueryKey, revision).
//
// Threads: PlaneNear, QueryKey and the other const methods may run on any number of threads at once, but not
// while Insert, RemoveFarFrom or Clear runs.
#pragma once

#include <absl/container/flat_hash_map.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "odometry/estimator/config/voxel_map_config.h"
#include "odometry/estimator/lidar/plane_fit.h"
#include "odometry/estimator/lidar/voxel_key.h"
#include "odometry/types/status.h"

namespace uf::estimator {

class VoxelHashMap {
 public:
  explicit VoxelHashMap(const VoxelMapConfig& config = {});  // asserts config.Validate().ok()

  // Adds world points (non-finite ones are skipped); voxels keep <= max_points_per_voxel points. rings: the
  // LiDAR ring of each point (-1 or missing: unknown), for the gate min_plane_rings.
  void Insert(const std::vector<Eigen::Vector3d>& world_points, const std::vector<int>& rings = {});
  // Bounded memory: drops every voxel whose centre is farther than max_range_m from `center`.
  void RemoveFarFrom(const Eigen::Vector3d& center);
  // The plane of the voxel holding world_point (see the top of this file), or nullopt when the block has
  // fewer than min_plane_points points, fails the eigen-ratio gate, or holds fewer than min_plane_rings
  // distinct rings (only when every point of the block has a known ring). Thread-safe (const, no cache).
  std::optional<Plane> PlaneNear(const Eigen::Vector3d& world_point) const;
  // What PlaneNear's answer depends on: the packed key of the voxel holding world_point, or kNoQueryKey for
  // a point PlaneNear rejects (non-finite, beyond the key range). While revision() is unchanged, points
  // with the same key get the same PlaneNear (callers cache planes per point across ICP rounds).
  static constexpr std::uint64_t kNoQueryKey = ~std::uint64_t{0};
  std::uint64_t QueryKey(const Eigen::Vector3d& world_point) const;
  // Counts the changes of the map (Insert, RemoveFarFrom, Clear).
  std::uint64_t revision() const { return revision_; }

  std::size_t voxel_count() const { return slot_of_.size(); }
  std::size_t point_count() const { return point_count_; }
  std::vector<Eigen::Vector3d> Points() const;  // all stored points (for viewers and tests), any order
  // This map seen through voxels `factor` times wider; `coarse` is the new map's config, its voxel_m factor
  // times this one's. Each coarse voxel gets the moments (and rings) of this map's voxels inside it, so its
  // planes are fitted from every point this map keeps, whatever max_points_per_voxel; it keeps no points
  // itself (Points() and point_count() are empty). One pass over the voxels.
  VoxelHashMap Coarsened(int factor, const VoxelMapConfig& coarse) const;
  void Clear();
  const VoxelMapConfig& config() const { return config_; }
  // config().min_plane_rings, or what its auto (0) stands for given the rings inserted so far.
  int min_plane_rings_in_use() const;

 private:
  // Slot of a voxel in voxels_; the 27 voxels of a block are linked by slot so that fitting the block of a
  // voxel with points costs no hash lookups. Block offset o = 9 (dx + 1) + 3 (dy + 1) + (dz + 1); 13 is the
  // voxel itself and 26 - o the opposite offset.
  using Slot = std::int32_t;
  static constexpr Slot kNoVoxel = -1;
  static constexpr int kBlockSize = 27;

  struct Voxel {
    VoxelIndex index;
    bool alive = false;
    std::array<Slot, kBlockSize> block;   // slots of the block's voxels, kNoVoxel where empty
    std::vector<Eigen::Vector3f> points;  // world, m (float: 30 um at 500 m, plenty for display)
    PointMoments moments;                 // relative to the voxel centre, double
    std::uint64_t rings = 0;              // RingBit of each point's ring
  };

  Eigen::Vector3d CenterOf(const VoxelIndex& index) const {
    return (index.cast<double>().array() + 0.5) * config_.voxel_m;
  }
  Slot Find(const VoxelIndex& index) const;
  Slot Create(const VoxelIndex& index);  // links the new voxel with its existing neighbours
  void Remove(Slot slot);
  std::optional<Plane> FitBlock(const Voxel& voxel) const;
  bool EnoughRings(std::uint64_t rings) const;  // the block's OR of Voxel::rings passes min_plane_rings
  std::optional<Plane> FitBlockAround(const VoxelIndex& index) const;  // for a voxel that holds no points
  // The plane of the block whose voxels are `slots` (by block offset), middle voxel centred at `centre`.
  std::optional<Plane> FitSlots(const std::array<Slot, kBlockSize>& slots,
                                const Eigen::Vector3d& centre) const;

  VoxelMapConfig config_;
  PlaneFitGate gate_;
  double inverse_voxel_m_;
  std::array<double, kBlockSize> weight_;          // per block offset: neighbour_weight^(|dx| + |dy| + |dz|)
  std::array<Eigen::Vector3d, kBlockSize> shift_;  // per block offset: (dx, dy, dz) voxel_m
  std::vector<Voxel> voxels_;  // slots; dead slots are reused through free_slots_
  std::vector<Slot> free_slots_;
  absl::flat_hash_map<std::uint64_t, Slot, VoxelKeyHash> slot_of_;
  std::size_t point_count_ = 0;
  std::uint64_t revision_ = 0;
  int highest_ring_ = -1;  // of every point inserted, Clear included: a property of the LiDAR
};

}  // namespace uf::estimator
