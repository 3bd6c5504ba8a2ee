#include "odometry/estimator/config/voxel_map_config.h"

#include <string>

namespace uf::estimator {
namespace {

Status FieldError(const std::string& field, const std::string& rule, double value) {
  return Status::Error("lidar_map." + field + ": must be " + rule + ", got " + std::to_string(value));
}

}  // namespace

Status VoxelMapConfig::Validate() const {
  if (!(voxel_m > 0 && voxel_m <= 10)) return FieldError("voxel_m", "in (0, 10]", voxel_m);
  if (max_points_per_voxel < 1) return FieldError("max_points_per_voxel", ">= 1", max_points_per_voxel);
  if (!(max_range_m > 0)) return FieldError("max_range_m", "> 0", max_range_m);
  if (!(plane_eigen_ratio > 0 && plane_eigen_ratio <= 1))
    return FieldError("plane_eigen_ratio", "in (0, 1]", plane_eigen_ratio);
  if (!(neighbour_weight > 0 && neighbour_weight <= 1))
    return FieldError("neighbour_weight", "in (0, 1]", neighbour_weight);
  if (min_plane_points < 3) return FieldError("min_plane_points", ">= 3", min_plane_points);
  if (!(min_plane_sigma_m >= 0)) return FieldError("min_plane_sigma_m", ">= 0", min_plane_sigma_m);
  if (min_plane_rings < 0 || min_plane_rings > 63)
    return FieldError("min_plane_rings", "in [0, 63] (0: auto)", min_plane_rings);
  return {};
}

}  // namespace uf::estimator
