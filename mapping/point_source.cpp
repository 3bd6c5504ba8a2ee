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

}  // namespace uf::mapping
