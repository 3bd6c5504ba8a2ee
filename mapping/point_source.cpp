#include "mapping/point_source.h"

#include <algorithm>
#include <cassert>

namespace uf::mapping {

VectorPointSource::VectorPointSource(std::vector<MapPoint> points, std::size_t chunk_size)
    : points_(std::move(points)), chunk_size_(chunk_size) {
  assert(chunk_size_ > 0);
  for (const MapPoint& p : points_) bounds_.extend(p.position);
}

bool VectorPointSource::ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const {
  for (std::size_t begin = 0; begin < points_.size(); begin += chunk_size_) {
    const std::size_t n = std::min(chunk_size_, points_.size() - begin);
    if (!chunk(std::span<const MapPoint>(points_.data() + begin, n))) return false;
  }
  return true;
}

TransformedPointSource::TransformedPointSource(const PointSource& source, const SE3& T)
    : source_(source), T_(T) {}

Eigen::AlignedBox3d TransformedPointSource::bounds() const {
  const Eigen::AlignedBox3d box = source_.bounds();
  Eigen::AlignedBox3d moved;
  if (box.isEmpty()) return moved;
  for (int corner = 0; corner < 8; ++corner)
    moved.extend(T_ * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  return moved;
}

bool TransformedPointSource::ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const {
  std::vector<MapPoint> moved;
  const Eigen::Matrix3f R = T_.rotation().cast<float>();
  return source_.ForEachChunk([&](std::span<const MapPoint> points) {
    moved.assign(points.begin(), points.end());
    for (MapPoint& p : moved) {
      p.position = T_ * p.position;
      p.normal = R * p.normal;
    }
    return chunk(moved);
  });
}

}  // namespace uf::mapping
