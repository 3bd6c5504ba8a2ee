#include "mapping/global_map.h"

#include <openvdb/tools/Prune.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>

#include "mapping/global_map_impl.h"

namespace uf::mapping {
namespace {

std::string Got(double value) {
  std::string text = std::to_string(value);
  return ", got " + text;
}

}  // namespace

Status GlobalMapConfig::Validate() const {
  if (!(voxel_size_m >= 0.001 && voxel_size_m <= 100.0))
    return Status::Error("map.voxel_size_m: must be in [0.001, 100]" + Got(voxel_size_m));
  if (max_voxels < 1 || max_voxels > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    return Status::Error("map.max_voxels: must be in [1, 2147483647], got " + std::to_string(max_voxels));
  if (min_observations < 1)
    return Status::Error("map.min_observations: must be >= 1, got " + std::to_string(min_observations));
  if (min_neighbors_if_unconfirmed < 0 || min_neighbors_if_unconfirmed > 27)
    return Status::Error("map.min_neighbors_if_unconfirmed: must be in [0, 27], got " +
                         std::to_string(min_neighbors_if_unconfirmed));
  if (color_min_samples < 2)
    return Status::Error("map.color_min_samples: must be >= 2, got " + std::to_string(color_min_samples));
  if (!(color_outlier_sigma > 0.0 && std::isfinite(color_outlier_sigma)))
    return Status::Error("map.color_outlier_sigma: must be finite and > 0" + Got(color_outlier_sigma));
  if (!(color_sigma_floor >= 0.0 && std::isfinite(color_sigma_floor)))
    return Status::Error("map.color_sigma_floor: must be finite and >= 0" + Got(color_sigma_floor));
  if (normal_radius_voxels < 1 || normal_radius_voxels > 4)
    return Status::Error("map.normal_radius_voxels: must be in [1, 4], got " +
                         std::to_string(normal_radius_voxels));
  return {};
}

openvdb::math::Transform::Ptr VoxelTransform(double voxel_size_m) {
  return openvdb::math::Transform::createLinearTransform(voxel_size_m);
}

GlobalMap::Impl::Impl(const GlobalMapConfig& c) : config(c) {
  openvdb::initialize();  // idempotent; registers the grid types for I/O
  index = openvdb::Int32Grid::create(-1);
  index->setTransform(VoxelTransform(config.voxel_size_m));
  index->setName("voxel_index");  // the grid map.vdb holds (map_file.h)
}

void GlobalMap::Impl::Evict() {
  const std::size_t n = voxels.size();
  const std::size_t keep = std::min(n, config.max_voxels - config.max_voxels / 10);
  const std::size_t drop = std::max<std::size_t>(n - keep, n >= config.max_voxels ? 1 : 0);
  if (drop == 0) return;
  // Victims: oldest last_stamp first, then farthest from the latest sensor origin, then index (a total
  // order, so eviction is deterministic).
  std::vector<std::tuple<Stamp, double, std::uint32_t>> order(n);
  for (std::size_t i = 0; i < n; ++i)
    order[i] = {voxels[i].last_stamp, -(Position(voxels[i]) - latest_origin).squaredNorm(),
                static_cast<std::uint32_t>(i)};
  std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(drop - 1), order.end());
  std::vector<bool> evicted(n, false);
  auto accessor = index->getAccessor();
  for (std::size_t k = 0; k < drop; ++k) {
    const std::uint32_t i = std::get<2>(order[k]);
    evicted[i] = true;
    accessor.setValueOff(voxels[i].ijk, -1);
  }
  // Compact the attribute array in place, keeping the order of the survivors, and re-point the grid.
  std::size_t write = 0;
  for (std::size_t read = 0; read < n; ++read) {
    if (evicted[read]) continue;
    if (write != read) {
      voxels[write] = voxels[read];
      accessor.setValueOnly(voxels[write].ijk, static_cast<std::int32_t>(write));
    }
    ++write;
  }
  voxels.resize(write);
  accessor.clear();
  openvdb::tools::pruneInactive(index->tree());
  stats.voxels_evicted += drop;
}

GlobalMap::GlobalMap(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlobalMap::GlobalMap(GlobalMap&&) noexcept = default;
GlobalMap& GlobalMap::operator=(GlobalMap&&) noexcept = default;
GlobalMap::~GlobalMap() = default;

Expected<GlobalMap> GlobalMap::Create(const GlobalMapConfig& config) {
  if (Status s = config.Validate(); !s.ok()) return s;
  return GlobalMap(std::make_unique<Impl>(config));
}

Status GlobalMap::Insert(const WorldScan& scan) {
  const std::size_t n = scan.points.size();
  if (!scan.intensity.empty() && scan.intensity.size() != n)
    return Status::Error("map insert: " + std::to_string(scan.intensity.size()) + " intensities for " +
                         std::to_string(n) + " points");
  if (!scan.colors.empty() && scan.colors.size() != n)
    return Status::Error("map insert: " + std::to_string(scan.colors.size()) + " colours for " +
                         std::to_string(n) + " points");
  Impl& map = *impl_;
  if (scan.sensor_origin_world.allFinite()) map.latest_origin = scan.sensor_origin_world;
  ++map.revision;
  const GlobalMapConfig& config = map.config;
  const float gate_k = static_cast<float>(config.color_outlier_sigma);
  const float sigma_floor = static_cast<float>(config.color_sigma_floor);
  const auto min_color_samples = static_cast<std::uint32_t>(config.color_min_samples);
  auto accessor = map.index->getAccessor();
  const std::uint64_t skipped_before = map.stats.points_skipped_invalid;

  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = scan.points[i].cast<double>();
    const std::optional<openvdb::Coord> ijk = map.VoxelOf(p);
    if (!ijk) {
      ++map.stats.points_skipped_invalid;
      continue;
    }
    std::int32_t slot = -1;
    if (!accessor.probeValue(*ijk, slot)) {
      if (map.voxels.size() >= config.max_voxels) {
        map.Evict();
        accessor.clear();  // the tree was pruned: drop cached node pointers
      }
      slot = static_cast<std::int32_t>(map.voxels.size());
      map.voxels.emplace_back().ijk = *ijk;
      accessor.setValue(*ijk, slot);
    }
    VoxelData& v = map.voxels[static_cast<std::size_t>(slot)];
    // Running means: m_n = m_{n-1} + (x_n - m_{n-1}) / n, the offset taken from the exact voxel centre.
    const float inv_n = 1.0f / static_cast<float>(++v.count);
    const Eigen::Vector3f offset = (p - map.Centre(*ijk)).cast<float>();
    v.offset_mean += (offset - v.offset_mean) * inv_n;
    const float intensity = scan.intensity.empty() ? 0.0f : scan.intensity[i];
    v.intensity_mean += (intensity - v.intensity_mean) * inv_n;
    v.last_stamp = std::max(v.last_stamp, scan.stamp);
    const Eigen::Vector3f to_sensor = (scan.sensor_origin_world - p).cast<float>();
    const float distance = to_sensor.norm();
    if (distance > 0 && std::isfinite(distance)) v.view_sum += to_sensor / distance;

    if (scan.colors.empty() || !scan.colors[i]) continue;
    const auto& rgb = *scan.colors[i];
    const Eigen::Vector3f c(rgb[0], rgb[1], rgb[2]);
    if (v.color_count >= min_color_samples) {
      // Gate: |c - mean| <= k * max(sigma, floor), sigma^2 = M2 / (n - 1) (sample variance summed over
      // channels, i.e. the mean squared distance of a colour from the mean).
      const float sigma = std::sqrt(v.color_m2 / static_cast<float>(v.color_count - 1));
      if ((c - v.color_mean).norm() > gate_k * std::max(sigma, sigma_floor)) {
        ++map.stats.colors_rejected;
        continue;
      }
    }
    // Welford's update of the mean and of M2 = sum |c_i - mean|^2.
    const Eigen::Vector3f delta = c - v.color_mean;
    v.color_mean += delta / static_cast<float>(++v.color_count);
    v.color_m2 += delta.dot(c - v.color_mean);
  }
  map.stats.points_inserted += n - (map.stats.points_skipped_invalid - skipped_before);
  return {};
}

Status GlobalMap::Insert(const Keyframe& keyframe, std::span<const PointColor> colors) {
  WorldScan scan;
  scan.stamp = keyframe.stamp;
  scan.sensor_origin_world = keyframe.T_world_body.translation();
  scan.points = keyframe.scan_world;
  scan.intensity = keyframe.scan_intensity;
  scan.colors = colors;
  return Insert(scan);
}

const GlobalMapConfig& GlobalMap::config() const { return impl_->config; }

GlobalMapStats GlobalMap::stats() const {
  GlobalMapStats stats = impl_->stats;
  stats.voxels = impl_->voxels.size();
  stats.memory_bytes = impl_->voxels.capacity() * sizeof(VoxelData) + impl_->index->memUsage();
  return stats;
}

std::size_t GlobalMap::size() const { return impl_->voxels.size(); }
std::uint64_t GlobalMap::revision() const { return impl_->revision; }

}  // namespace uf::mapping
