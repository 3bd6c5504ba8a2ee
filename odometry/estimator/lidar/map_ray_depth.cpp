#include "odometry/estimator/lidar/map_ray_depth.h"

#include <cmath>

namespace uf::estimator {
namespace {

constexpr double kMinIncidence = 0.1;    // |cos| of the ray to the plane's normal: below it the ray grazes
constexpr double kBlockHalfWidth = 1.5;  // voxels: a plane comes from the 3x3x3 block about its voxel

}  // namespace

std::optional<MapRayHit> MapRaySurface(const VoxelHashMap& map, const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction, double min_m, double max_m) {
  if (!origin.allFinite() || !direction.allFinite() || !(min_m >= 0) || !(max_m > min_m)) return std::nullopt;
  const double step = map.config().voxel_m;
  const double reach = kBlockHalfWidth * step;
  for (double t = min_m; t <= max_m; t += step) {
    const Eigen::Vector3d sample = origin + t * direction;
    const std::optional<Plane> plane = map.PlaneNear(sample);
    if (!plane) continue;
    // origin + s d on the plane: n . (origin + s d - q) = 0.
    const double incidence = plane->normal.dot(direction);
    if (std::abs(incidence) < kMinIncidence) continue;
    const double s = plane->normal.dot(plane->point - origin) / incidence;
    if (!(s >= min_m && s <= max_m)) continue;
    if (((origin + s * direction) - sample).cwiseAbs().maxCoeff() > reach) continue;
    return MapRayHit{s, *plane};
  }
  return std::nullopt;
}

}  // namespace uf::estimator
