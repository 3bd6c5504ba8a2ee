// Edge-alignment score of a LiDAR-camera calibration (after Levinson & Thrun, "Automatic Online
// Calibration of Cameras and Lasers", RSS 2013): depth discontinuities of the projected scan should fall
// on intensity edges of the image.
//
//   E(x)  = |Sobel(grey)|(x), grey = 0.299 R + 0.587 G + 0.114 B          (image edge strength)
//   S(x)  = max_y E(y) g^(|x_u - y_u| + |x_v - y_v|),  g = 2^(-1 / edge_spread_px)
//           (edges spread over a few pixels, halving every edge_spread_px pixels along each axis, so that
//           a small misalignment is penalised smoothly rather than all-or-nothing)
//   score = mean of S over the depth-edge points / mean of S over all visible points
//
// A visible point is a depth-edge point when another visible point in the same rows (within
// edge_rows_px) and at most edge_window_px columns away, or in the same columns and at most
// edge_window_px rows away, lies farther by more than max(min_depth_jump_m, min_depth_jump_ratio * depth):
// the point is on the near side of a silhouette (the side whose outline the image shows). Both
// directions count, so that vertical outlines (poles) constrain yaw and horizontal ones (roofs, tops of
// walls) pitch. Score 1 means no relation between depth edges and image
// edges; higher is better aligned. Rotating a good extrinsic by a degree lowers it.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "mapping/colorize_projection.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"

namespace uf::mapping {

struct EdgeAlignmentOptions {
  int edge_spread_px = 4;             // in [1, 64]: image edges halve their weight every this many pixels
  int edge_window_px = 12;            // in [1, 256]: columns (rows) searched for a farther neighbour
  int edge_rows_px = 1;               // in [0, 16]: rows (columns) either side searched too
  double min_depth_jump_m = 1.0;      // >= 0: smallest depth step that makes a depth edge
  double min_depth_jump_ratio = 0.3;  // >= 0: ... relative to the point's depth
  VisibilityOptions visibility;       // which points count (occluded ones do not)
};

Status ValidateEdgeAlignmentOptions(const EdgeAlignmentOptions& options);

struct EdgeAlignment {
  double score = 0;             // see above; 0 when there is no depth-edge point
  std::size_t edge_points = 0;  // visible points on a depth edge
  std::size_t visible_points = 0;
};

// Holds S (above) for one image, so that several extrinsics are scored against it cheaply.
class EdgeAlignmentScorer {
 public:
  // `image` 8-bit gray or RGB; options assumed valid (see ValidateEdgeAlignmentOptions).
  EdgeAlignmentScorer(const Image& image, const EdgeAlignmentOptions& options = {});

  // The score of the points seen by `camera` (of the image's size) at T_world_cam.
  EdgeAlignment Score(std::span<const Eigen::Vector3f> points_world, const CameraModel& camera,
                      const SE3& T_world_cam) const;
  // The same for points already projected (ProjectWithOcclusion with options.visibility).
  EdgeAlignment Score(const ProjectedScan& scan) const;

  // S at a pixel (bilinear), for tests and overlays.
  float Spread(const Eigen::Vector2f& pixel) const;

 private:
  EdgeAlignmentOptions options_;
  int width_, height_;
  std::vector<float> spread_;  // S, row-major
};

// Flags of the depth-edge points of a projected scan (see above); non-visible points are never edges.
std::vector<bool> FindDepthEdges(const ProjectedScan& scan, int width, int height,
                                 const EdgeAlignmentOptions& options);

}  // namespace uf::mapping
