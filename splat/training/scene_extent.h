// The scene extent of splat training: the radius of the training cameras' centres around their centroid,
//   c = (1/n) sum_i p_i,  extent = max(max_i |p_i - c|, 1e-3) m,
// as 3DGS uses it to scale the position learning rate (learning_rate.h), densification and the size pruning
// (densify.h). 1e-3 without cameras, or when they all stand at one place.
#pragma once

#include <Eigen/Core>
#include <span>

namespace uf::splat {

double SceneExtent(std::span<const Eigen::Vector3d> camera_centres);

}  // namespace uf::splat
