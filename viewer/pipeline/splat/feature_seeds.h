// Gaussians for what the camera sees and the LiDAR did not reach: corners tracked across the training images
// and triangulated with the run's camera poses (the sparse points 3DGS gets from structure from motion).
// A spinning LiDAR covers a band of elevations (KITTI's HDL-64E: +2 to -25 deg), so tree crowns, the upper
// floors of buildings and signs above it have no map point; without seeds they can only be learned by the
// sky sphere, at the sphere's depth, which is wrong in every other view.
//
// The training views are tracked in time order by the visual front end (odometry/estimator/visual/
// feature_tracker.h, at the training resolution); a track seen in >= 2 views is triangulated
// (visual/triangulation.h) and kept when
//   - its rays span >= min_parallax_deg (otherwise its depth is not observed),
//   - it is >= min_depth_m in front of every camera and <= max_depth_m from the first,
//   - it reprojects within max_reprojection_px in every view, and
//   - no map seed lies within map_clearance_m (where the LiDAR saw, its points are the better seeds).
// Each point becomes a round Gaussian of the mean colour of its observations, sized to the spacing of the
// corners at its depth (min_distance_px seen from the nearest camera), at the map seeds' initial opacity.
#pragma once

#include <cstddef>
#include <vector>

#include "odometry/types/status.h"
#include "splat/gaussian_model.h"
#include "viewer/pipeline/splat/splat_views.h"

namespace uf::pipeline {

struct FeatureSeedOptions {
  int max_features = 600;          // corners per image
  double min_distance_px = 4;      // between corners, training pixels
  double min_parallax_deg = 2;     // between the rays of a track
  double min_depth_m = 1;          // in front of each camera
  double max_depth_m = 150;        // from the first camera that saw it
  double max_reprojection_px = 1;  // in every view
  double map_clearance_m = 0.5;    // no map seed this close
  double initial_opacity = 0.5;
};

struct FeatureSeedStats {
  std::size_t tracks = 0;        // seen in >= 2 training views
  std::size_t triangulated = 0;  // passed parallax, depth and reprojection
  std::size_t near_map = 0;      // of those, left out: a map seed within map_clearance_m
  std::size_t added = 0;         // Gaussians appended to the model
};

// Appends the seeds to `model`, whose first `map_seeds` Gaussians are the map's. Fails only for an invalid
// tracker (the views' size or intrinsics).
Expected<FeatureSeedStats> AddFeatureSeeds(splat::GaussianModel& model, std::size_t map_seeds,
                                           const std::vector<StoredView>& train,
                                           const FeatureSeedOptions& options = {});

}  // namespace uf::pipeline
