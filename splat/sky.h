// The sky of splat training: Gaussians on a sphere beyond the map (AddBackgroundSphere, seeding.h) for what
// the LiDAR map does not hold (sky, far background), sized from the seeded model and the training cameras.
//
//   centre  c = (1/n) sum_i p_i over the n training camera centres p_i;
//   radius  r = max(10 m, 1.2 d_95), d_95 the 95th percentile of the seeded Gaussians' distances from c
//           (the element of rank floor(0.95 (m - 1)) among the m distances, 0-based; 10 m without Gaussians),
//           then reduced to r <= s_max sqrt(count / (4 pi)), so that the lattice spacing r sqrt(4 pi / count)
//           stays under s_max = prune_world_fraction x SceneExtent(p) (training/scene_extent.h): the discs
//           (tangent scale half the spacing) then stay under half the size-pruning limit and survive pruning;
//   count   Gaussians, opacity kSkyOpacity, grey.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "splat/gaussian_model.h"

namespace uf::splat {

constexpr double kSkyOpacity = 0.5;

struct SkySphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;  // m
};

// Adds `count` sky Gaussians to `model` (see the top of this file) and returns the sphere they lie on; adds
// nothing and returns none without camera centres or for count <= 0.
std::optional<SkySphere> AddSky(GaussianModel& model, std::span<const Eigen::Vector3d> camera_centres,
                                int count, double prune_world_fraction);

}  // namespace uf::splat
