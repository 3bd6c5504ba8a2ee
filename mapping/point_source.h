// A read-only source of map points that is read in chunks, so writers stream a map of any size with bounded
// memory. The global map's MapView implements it; tests and small tools use VectorPointSource.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "mapping/map_point.h"
#include "odometry/types/se3.h"

namespace uf::mapping {

class PointSource {
 public:
  virtual ~PointSource() = default;
  // Number of points ForEachChunk delivers.
  virtual std::size_t size() const = 0;
  // Axis-aligned bounds of all positions (empty box when size() == 0).
  virtual Eigen::AlignedBox3d bounds() const = 0;
  // Calls `chunk` with consecutive spans covering every point exactly once, in a deterministic order; a span
  // is valid only during its call. Stops early and returns false when `chunk` returns false.
  virtual bool ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const = 0;
};

// A PointSource over points held in memory, delivered in chunks of `chunk_size`.
class VectorPointSource final : public PointSource {
 public:
  explicit VectorPointSource(std::vector<MapPoint> points, std::size_t chunk_size = 65536);
  std::size_t size() const override { return points_.size(); }
  Eigen::AlignedBox3d bounds() const override { return bounds_; }
  bool ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const override;

 private:
  std::vector<MapPoint> points_;
  std::size_t chunk_size_;
  Eigen::AlignedBox3d bounds_;
};

// Another source's points moved by a rigid transform (positions and normals): p' = T p. Used to write a map
// in the east-north-up frame it was aligned to (map_file.h MapGeoreference::T_enu_map).
class TransformedPointSource final : public PointSource {
 public:
  // `source` must outlive this.
  TransformedPointSource(const PointSource& source, const SE3& T);
  std::size_t size() const override { return source_.size(); }
  Eigen::AlignedBox3d bounds() const override;  // of the transformed box corners (contains every point)
  bool ForEachChunk(const std::function<bool(std::span<const MapPoint>)>& chunk) const override;

 private:
  const PointSource& source_;
  SE3 T_;
};

}  // namespace uf::mapping
