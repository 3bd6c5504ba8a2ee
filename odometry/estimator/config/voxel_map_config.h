// Configuration of the LiDAR local map (voxel_hash_map.h): voxel size, points per voxel, range, and the
// plane gate of its PCA planes.
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct VoxelMapConfig {
  double voxel_m = 0.5;             // voxel edge, m (paper: 0.5)
  int max_points_per_voxel = 20;    // points kept per voxel
  double max_range_m = 100;         // RemoveFarFrom drops voxels whose centre is farther than this, m
  double plane_eigen_ratio = 0.12;  // plane gate lambda_min / lambda_mid (paper: 0.12)
  int min_plane_points = 5;         // points needed in the 3x3x3 block for a plane
  double min_plane_sigma_m = 0.05;  // floor of Plane::sigma, m
  // Where a voxel's plane passes: through the centroid of its 3x3x3 block with each neighbour's points
  // weighted w per axis it is offset along (face neighbours w, edge ones w^2, corner ones w^3, the voxel
  // itself 1: a Gaussian kernel of sigma voxel_m / sqrt(2 ln(1 / w)), 0.6 voxel at 0.25). 1: the block's
  // plain centroid, from which a curved surface (a trunk, a crown, a bank) bends away. The normal, sigma and
  // gates stay the whole block's (docs/METHOD.md "Voxel-hash map and PCA planes").
  double neighbour_weight = 0.25;
  // Distinct LiDAR rings needed in the 3x3x3 block for a plane, when every point's ring is known (1: off).
  // One ring is one scan line: a curve on the beam's cone, whose PCA plane may be the cone's, not the
  // surface's. 0: auto, 2 once a point of ring kAutoGateFromRing or higher was inserted (a LiDAR of 32 rings
  // or more), else 1: a sparser LiDAR's rings lie metres apart on the ground, where a block holds one.
  int min_plane_rings = 0;
  static constexpr int kAutoGateFromRing = 31;

  // "lidar_map.<field>: must be ..., got <value>" for the first bad field.
  Status Validate() const;
};

}  // namespace uf::estimator
