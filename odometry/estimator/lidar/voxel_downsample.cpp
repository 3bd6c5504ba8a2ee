#include "odometry/estimator/lidar/voxel_downsample.h"

#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "odometry/estimator/lidar/voxel_key.h"

namespace uf::estimator {
namespace {

// Open-addressing set of packed voxel keys with linear probing; key ~0 marks an empty slot (it would be
// the voxel (-1, -1, -1) with the 64th bit set, which PackVoxelKey never produces).
class VoxelKeySet {
 public:
  explicit VoxelKeySet(std::size_t expected) {
    const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * expected));
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
  }
  // True when the key was not in the set yet (and is now).
  bool Insert(std::uint64_t key) {
    for (std::size_t i = VoxelKeyHash()(key) & mask_;; i = (i + 1) & mask_) {
      if (slots_[i] == key) return false;
      if (slots_[i] == kEmpty) {
        slots_[i] = key;
        return true;
      }
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::vector<std::uint64_t> slots_;
  std::size_t mask_ = 0;
};

}  // namespace

std::vector<LidarPoint> VoxelDownsample(const std::vector<LidarPoint>& points, double voxel_m) {
  assert(voxel_m > 0);
  const double inverse_voxel = 1.0 / voxel_m;
  const double limit = static_cast<double>(kVoxelIndexLimit) * voxel_m;
  // The set never holds more keys than points, so at most half full: probes stay short.
  VoxelKeySet seen(points.size());
  std::vector<LidarPoint> kept;
  kept.reserve(points.size() / 4);
  for (const LidarPoint& point : points) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() >= limit) continue;
    if (seen.Insert(PackVoxelKey(VoxelOf(p, inverse_voxel)))) kept.push_back(point);
  }
  return kept;
}

}  // namespace uf::estimator
