#include "odometry/estimator/lidar/voxel_hash_map.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <string>

namespace uf::estimator {
namespace {

// Block offset o = 9 (dx + 1) + 3 (dy + 1) + (dz + 1) and back.
VoxelIndex OffsetOf(int o) { return VoxelIndex(o / 9 - 1, (o / 3) % 3 - 1, o % 3 - 1); }
constexpr int kSelf = 13;

// Rings as a 64-bit set: ring r sets bit r % 63 (rings 63 apart share a bit: on a 128-ring sensor they are
// tens of degrees apart, never both in one block at a range where a block could hold one line), an unknown
// ring sets bit 63, which lifts the ring gate for the block.
constexpr std::uint64_t kUnknownRing = std::uint64_t{1} << 63;
std::uint64_t RingBit(int ring) { return ring < 0 ? kUnknownRing : std::uint64_t{1} << (ring % 63); }

}  // namespace

VoxelHashMap::VoxelHashMap(const VoxelMapConfig& config)
    : config_(config),
      gate_{config.plane_eigen_ratio, config.min_plane_points, config.min_plane_sigma_m},
      inverse_voxel_m_(1.0 / config.voxel_m) {
  assert(config.Validate().ok());
  for (int o = 0; o < kBlockSize; ++o) {
    const VoxelIndex offset = OffsetOf(o);
    weight_[o] = std::pow(config.neighbour_weight, offset.cwiseAbs().sum());
    shift_[o] = offset.cast<double>() * config.voxel_m;
  }
}

VoxelHashMap::Slot VoxelHashMap::Find(const VoxelIndex& index) const {
  const auto it = slot_of_.find(PackVoxelKey(index));
  return it == slot_of_.end() ? kNoVoxel : it->second;
}

VoxelHashMap::Slot VoxelHashMap::Create(const VoxelIndex& index) {
  Slot slot;
  if (free_slots_.empty()) {
    slot = static_cast<Slot>(voxels_.size());
    voxels_.emplace_back();
  } else {
    slot = free_slots_.back();
    free_slots_.pop_back();
  }
  slot_of_.emplace(PackVoxelKey(index), slot);
  Voxel& voxel = voxels_[slot];
  voxel.index = index;
  voxel.alive = true;
  voxel.points.clear();
  voxel.points.reserve(config_.max_points_per_voxel);
  voxel.moments = PointMoments();
  voxel.rings = 0;
  for (int o = 0; o < kBlockSize; ++o) {
    const Slot neighbour = o == kSelf ? slot : Find(index + OffsetOf(o));
    voxel.block[o] = neighbour;
    if (neighbour != kNoVoxel && o != kSelf) voxels_[neighbour].block[kBlockSize - 1 - o] = slot;
  }
  return slot;
}

void VoxelHashMap::Remove(Slot slot) {
  Voxel& voxel = voxels_[slot];
  for (int o = 0; o < kBlockSize; ++o) {
    const Slot neighbour = voxel.block[o];
    if (neighbour == kNoVoxel || o == kSelf) continue;
    voxels_[neighbour].block[kBlockSize - 1 - o] = kNoVoxel;
  }
  point_count_ -= voxel.points.size();
  slot_of_.erase(PackVoxelKey(voxel.index));
  voxel.alive = false;
  voxel.points = {};  // gives the memory back
  free_slots_.push_back(slot);
}

void VoxelHashMap::Insert(const std::vector<Eigen::Vector3d>& world_points, const std::vector<int>& rings) {
  ++revision_;
  const double limit = static_cast<double>(kVoxelIndexLimit - 2) * config_.voxel_m;
  for (std::size_t k = 0; k < world_points.size(); ++k) {
    const Eigen::Vector3d& p = world_points[k];
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() >= limit) continue;
    const VoxelIndex index = VoxelOf(p, inverse_voxel_m_);
    Slot slot = Find(index);
    if (slot == kNoVoxel) slot = Create(index);
    Voxel& voxel = voxels_[slot];  // after Create: voxels_ may have grown
    if (static_cast<int>(voxel.points.size()) >= config_.max_points_per_voxel) continue;
    voxel.points.push_back(p.cast<float>());
    voxel.moments.Add(p - CenterOf(index));
    const int ring = k < rings.size() ? rings[k] : -1;
    voxel.rings |= RingBit(ring);
    highest_ring_ = std::max(highest_ring_, ring);
    ++point_count_;
  }
}

void VoxelHashMap::RemoveFarFrom(const Eigen::Vector3d& center) {
  ++revision_;
  const double max_squared = config_.max_range_m * config_.max_range_m;
  for (Slot slot = 0; slot < static_cast<Slot>(voxels_.size()); ++slot)
    if (voxels_[slot].alive && (CenterOf(voxels_[slot].index) - center).squaredNorm() > max_squared)
      Remove(slot);
}

std::optional<Plane> VoxelHashMap::FitBlock(const Voxel& voxel) const {
  return FitSlots(voxel.block, CenterOf(voxel.index));
}

std::optional<Plane> VoxelHashMap::FitBlockAround(const VoxelIndex& index) const {
  std::array<Slot, kBlockSize> slots;
  for (int o = 0; o < kBlockSize; ++o) slots[o] = Find(index + OffsetOf(o));
  return FitSlots(slots, CenterOf(index));
}

std::optional<Plane> VoxelHashMap::FitSlots(const std::array<Slot, kBlockSize>& slots,
                                            const Eigen::Vector3d& centre) const {
  // Moments of the block relative to the centre c_v of the middle voxel v: a neighbour u's moments are
  // relative to c_u, so shift by c_u - c_v = (u - v) voxel_m. The normal, sigma and the gates come from the
  // whole block; the plane's point is the centroid weighted by the kernel (VoxelMapConfig::neighbour_weight).
  ShiftedMomentSum block;
  Eigen::Vector3d weighted_sum = Eigen::Vector3d::Zero();
  double weight = 0;
  std::uint64_t rings = 0;
  for (int o = 0; o < kBlockSize; ++o) {
    if (slots[o] == kNoVoxel) continue;
    const Voxel& u = voxels_[slots[o]];
    block.Add(u.moments, shift_[o]);
    weighted_sum += weight_[o] * (u.moments.sum + u.moments.count * shift_[o]);
    weight += weight_[o] * u.moments.count;
    rings |= u.rings;
  }
  if (!EnoughRings(rings)) return std::nullopt;
  std::optional<Plane> plane = FitPlane(block.Total(), centre, gate_);
  if (plane) plane->point = centre + weighted_sum / weight;
  return plane;
}

int VoxelHashMap::min_plane_rings_in_use() const {
  if (config_.min_plane_rings > 0) return config_.min_plane_rings;
  return highest_ring_ >= VoxelMapConfig::kAutoGateFromRing ? 2 : 1;
}

bool VoxelHashMap::EnoughRings(std::uint64_t rings) const {
  return (rings & kUnknownRing) != 0 || std::popcount(rings) >= min_plane_rings_in_use();
}

std::uint64_t VoxelHashMap::QueryKey(const Eigen::Vector3d& world_point) const {
  if (!world_point.allFinite()) return kNoQueryKey;
  if (world_point.cwiseAbs().maxCoeff() >= static_cast<double>(kVoxelIndexLimit - 2) * config_.voxel_m)
    return kNoQueryKey;
  return PackVoxelKey(VoxelOf(world_point, inverse_voxel_m_));
}

std::optional<Plane> VoxelHashMap::PlaneNear(const Eigen::Vector3d& world_point) const {
  if (!world_point.allFinite()) return std::nullopt;
  if (world_point.cwiseAbs().maxCoeff() >= static_cast<double>(kVoxelIndexLimit - 2) * config_.voxel_m)
    return std::nullopt;
  const VoxelIndex index = VoxelOf(world_point, inverse_voxel_m_);
  const Slot slot = Find(index);
  return slot == kNoVoxel ? FitBlockAround(index) : FitBlock(voxels_[slot]);
}

std::vector<Eigen::Vector3d> VoxelHashMap::Points() const {
  std::vector<Eigen::Vector3d> points;
  points.reserve(point_count_);
  for (const Voxel& voxel : voxels_)
    if (voxel.alive)
      for (const Eigen::Vector3f& p : voxel.points) points.push_back(p.cast<double>());
  return points;
}

VoxelHashMap VoxelHashMap::Coarsened(int factor, const VoxelMapConfig& coarse) const {
  assert(factor >= 1 && std::abs(coarse.voxel_m - factor * config_.voxel_m) <= 1e-9 * coarse.voxel_m);
  VoxelHashMap result(coarse);
  result.highest_ring_ = highest_ring_;
  const auto floor_div = [factor](int i) { return i >= 0 ? i / factor : -((-i + factor - 1) / factor); };
  std::vector<ShiftedMomentSum> sums;  // per slot of result, relative to its voxel's centre
  for (const Voxel& voxel : voxels_) {
    if (!voxel.alive) continue;
    const VoxelIndex index = voxel.index.unaryExpr(floor_div);
    Slot slot = result.Find(index);
    if (slot == kNoVoxel) slot = result.Create(index);
    if (static_cast<std::size_t>(slot) >= sums.size()) sums.resize(slot + 1);
    sums[slot].Add(voxel.moments, CenterOf(voxel.index) - result.CenterOf(index));
    result.voxels_[slot].rings |= voxel.rings;
  }
  for (std::size_t slot = 0; slot < sums.size(); ++slot) result.voxels_[slot].moments = sums[slot].Total();
  return result;
}

void VoxelHashMap::Clear() {
  ++revision_;
  voxels_.clear();
  free_slots_.clear();
  slot_of_.clear();
  point_count_ = 0;
}

}  // namespace uf::estimator
