#include "splat/sky.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "splat/seeding.h"
#include "splat/training/scene_extent.h"

namespace uf::splat {

std::optional<SkySphere> AddSky(GaussianModel& model, std::span<const Eigen::Vector3d> camera_centres,
                                int count, double prune_world_fraction) {
  if (camera_centres.empty() || count <= 0) return std::nullopt;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : camera_centres) centre += p / camera_centres.size();
  std::vector<double> distances;
  distances.reserve(model.size());
  for (const Eigen::Vector3f& p : model.positions) distances.push_back((p.cast<double>() - centre).norm());
  double radius = 10.0;
  if (!distances.empty()) {
    auto percentile = distances.begin() + static_cast<std::ptrdiff_t>(0.95 * (distances.size() - 1));
    std::nth_element(distances.begin(), percentile, distances.end());
    radius = std::max(radius, 1.2 * *percentile);
  }
  const double gaussians = count;
  const double largest_spacing = prune_world_fraction * SceneExtent(camera_centres);
  radius = std::min(radius, largest_spacing * std::sqrt(gaussians / (4 * M_PI)));
  AddBackgroundSphere(model, centre, radius, count, kSkyOpacity);
  return SkySphere{centre, radius};
}

}  // namespace uf::splat
