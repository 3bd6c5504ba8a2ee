// One point of the global map as later stages see it: a voxel's representative point with its colour,
// intensity, normal, observation count and last observation time. Positions are double precision in the
// map frame (the estimator's world frame; east-north-up at the georeference origin when there is one).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "odometry/types/stamp.h"

namespace uf::mapping {

struct MapPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // map frame, m
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();    // unit surface normal; zero when unknown
  std::array<std::uint8_t, 3> rgb = {0, 0, 0};         // sRGB colour; meaningful only if has_color
  bool has_color = false;
  float intensity = 0;     // mean LiDAR intensity, as the sensor reports it
  std::uint32_t count = 0;  // number of observations merged into this point
  Stamp last_stamp = 0;     // time of the latest observation, ns
};

}  // namespace uf::mapping
