// Gaussians seeded from the colorized map (the start of splat optimization): one Gaussian per map
// point, a flat disc on the local surface. When the map holds coloured points, only those are seeded (by
// default): an uncoloured point was in no camera image, so no training image can teach its Gaussian anything,
// and leaving them out spends the seed budget on what the cameras saw (on KITTI's 360-degree LiDAR with one
// forward camera, 64 % of the map).
//   mean      = the point;
//   colour    = the point's sRGB colour as the SH DC term (f_dc = (c - 0.5) / Y_0), higher bands zero;
//               uncoloured points are seeded grey (0.5) and counted;
//   scale     = s = sqrt(mean squared distance to the k nearest map points) along both tangent axes (the
//               3DGS initialization), flatness * s along the normal; points without a normal get s on all
//               three axes; points without neighbours within search_radius_m get s = search_radius_m / 2;
//   rotation  = the rotation taking the local z axis onto the normal (local x, y span the tangent plane);
//   opacity   = initial_opacity.
// Positions are converted to float relative to the map frame origin (sub-millimetre up to ~8 km away).
#pragma once

#include <cstddef>
#include <string>

#include "mapping/point_source.h"
#include "odometry/types/status.h"
#include "splat/gaussian_model.h"

namespace uf::splat {

struct SeedOptions {
  int sh_degree = 3;                      // degree the model is allocated for (higher bands start at zero)
  int neighbours = 3;                     // k of the spacing estimate
  double search_radius_m = 0.5;           // neighbours are looked for within this radius
  double flatness = 0.1;                  // normal-axis scale as a fraction of the tangent scale
  double initial_opacity = 0.5;           // in (0, 1)
  std::size_t max_gaussians = 4'000'000;  // more map points are thinned evenly (every n-th point)
  bool seen_points_only = true;           // a map with coloured points: leave its uncoloured ones out

  Status Validate() const;  // names the field and value
};

struct SeedResult {
  GaussianModel model;
  std::size_t map_points = 0;                    // points read from the map
  std::size_t uncoloured = 0;                    // seeded grey
  std::size_t unseen_left_out = 0;               // uncoloured points not seeded (seen_points_only)
  std::size_t without_normal = 0, isolated = 0;  // isotropic / default-scale seeds
  std::size_t thinning = 1;                      // every thinning-th map point left in was seeded
};

Expected<SeedResult> SeedGaussians(const mapping::PointSource& map, const SeedOptions& options = {});

// Gaussians for what the map does not hold (the sky, far background), as 3DGS' random far points do:
// `count` flat discs on a sphere of `radius` m around `centre` (a Fibonacci lattice: even spacing
// s = radius sqrt(4 pi / count)), each facing the centre (local z along the radius), tangent scale s / 2,
// normal scale s / 20, grey (0.5), opacity `opacity`. The optimizer colours them from the images.
void AddBackgroundSphere(GaussianModel& model, const Eigen::Vector3d& centre, double radius, int count,
                         double opacity);

}  // namespace uf::splat
