// Helpers shared by the mapping tests.
#pragma once

#include <span>
#include <vector>

#include "mapping/point_source.h"

namespace uf::mapping::testing {

// Every point a source delivers, in its order.
inline std::vector<MapPoint> AllPoints(const PointSource& source) {
  std::vector<MapPoint> points;
  source.ForEachChunk([&](std::span<const MapPoint> chunk) {
    points.insert(points.end(), chunk.begin(), chunk.end());
    return true;
  });
  return points;
}

}  // namespace uf::mapping::testing
