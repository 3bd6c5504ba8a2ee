#include "splat/training/scene_extent.h"

#include <algorithm>

namespace uf::splat {

double SceneExtent(std::span<const Eigen::Vector3d> camera_centres) {
  if (camera_centres.empty()) return 1e-3;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : camera_centres) centroid += p;
  centroid /= static_cast<double>(camera_centres.size());
  double radius = 0;
  for (const Eigen::Vector3d& p : camera_centres) radius = std::max(radius, (p - centroid).norm());
  return std::max(radius, 1e-3);
}

}  // namespace uf::splat
