// Integer voxel coordinates of a point and their packing into one 64-bit hash key, shared by the LiDAR
// downsampler and the voxel-hash map.
//
// Voxel index i = floor(x / voxel_m) per axis; voxel i spans [i voxel_m, (i + 1) voxel_m), centre
// (i + 1/2) voxel_m. The key packs each index in 21 bits (two's complement), so indices must lie in
// [-2^20, 2^20): +-524 km at 0.5 m voxels, +-105 km at 0.1 m.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

namespace uf::estimator {

using VoxelIndex = Eigen::Vector3i;

constexpr std::int64_t kVoxelIndexLimit = std::int64_t{1} << 20;

inline VoxelIndex VoxelOf(const Eigen::Vector3d& p, double inverse_voxel_m) {
  return VoxelIndex(static_cast<int>(std::floor(p.x() * inverse_voxel_m)),
                    static_cast<int>(std::floor(p.y() * inverse_voxel_m)),
                    static_cast<int>(std::floor(p.z() * inverse_voxel_m)));
}

inline std::uint64_t PackVoxelKey(const VoxelIndex& v) {
  assert(v.x() >= -kVoxelIndexLimit && v.x() < kVoxelIndexLimit && v.y() >= -kVoxelIndexLimit &&
         v.y() < kVoxelIndexLimit && v.z() >= -kVoxelIndexLimit && v.z() < kVoxelIndexLimit);
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  return (static_cast<std::uint64_t>(v.x()) & kMask) | ((static_cast<std::uint64_t>(v.y()) & kMask) << 21) |
         ((static_cast<std::uint64_t>(v.z()) & kMask) << 42);
}

// splitmix64's finaliser: spreads spatially close keys over the whole table.
struct VoxelKeyHash {
  std::size_t operator()(std::uint64_t key) const {
    key ^= key >> 30;
    key *= 0xbf58476d1ce4e5b9ULL;
    key ^= key >> 27;
    key *= 0x94d049bb133111ebULL;
    key ^= key >> 31;
    return static_cast<std::size_t>(key);
  }
};

// Open-addressing set of packed voxel keys with linear probing, sized for `expected` keys at most half
// full (probes stay short); key ~0 marks an empty slot (it would be the voxel (-1, -1, -1) with the 64th
// bit set, which PackVoxelKey never produces). Several times faster than std::unordered_set for the
// per-scan downsampling.
class VoxelKeySet {
 public:
  explicit VoxelKeySet(std::size_t expected) {
    const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * expected));
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
  }
  // True when the key was not in the set yet (and is now). At most `expected` keys may be inserted.
  bool Insert(std::uint64_t key) { return InsertSlot(key).inserted; }
  // The same, with the key's slot in [0, capacity()): fixed while the set lives, so callers can keep per-key
  // data in arrays of capacity() entries.
  struct Slot {
    std::size_t index;
    bool inserted;
  };
  Slot InsertSlot(std::uint64_t key) {
    for (std::size_t i = VoxelKeyHash()(key) & mask_;; i = (i + 1) & mask_) {
      if (slots_[i] == key) return {i, false};
      if (slots_[i] == kEmpty) {
        slots_[i] = key;
        return {i, true};
      }
    }
  }
  std::size_t capacity() const { return slots_.size(); }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::vector<std::uint64_t> slots_;
  std::size_t mask_ = 0;
};

}  // namespace uf::estimator
