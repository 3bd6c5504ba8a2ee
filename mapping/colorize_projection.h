// Projection of world-frame points into one camera image with a z-buffer occlusion test: the building
// block of the colorizer and of the edge-alignment score.
//
// Frames: T_world_cam maps camera-frame points (OpenCV axes: x right, y down, z forward) into the world,
// so p_cam = T_world_cam^-1 p_world. Depth is the z coordinate in the camera frame (m).
//
// Occlusion (a splatted z-buffer): every point that projects into the image writes its depth into a block
// of pixels around its pixel, keeping the nearest depth per pixel. A LiDAR scan is sparse in the image
// (rings several pixels apart), so the block must close the gaps between a surface's points, or background
// points seen through the gaps would take the foreground's colour. With the automatic splat, a point's
// block reaches half-way to its nearest neighbour of the same surface (depth within
// max(0.3 m, 10 %)) up, down, left and right (searched up to 64 pixels, within +-1 pixel across beyond 2
// pixels); in a direction without such a neighbour (an object's outline) it mirrors the opposite direction.
// The block thus adapts to the local density: dense far rings near the horizon get small blocks, a pole's
// sparse rings large ones. The depth written over the block follows the surface towards those neighbours
// (inverse depth is affine in the pixel on a plane), so a road or wall seen at a grazing angle, whose depth
// grows fast from row to row, does not hide its own farther points under a flat block. It is capped at max_automatic_half_size_px: through see-through structures
// (fence bars, foliage) the camera does see the background; on the recorded LiDAR-camera pair the uncapped
// splat leaves 70 % of the in-image points visible, a cap of 3 pixels 96 %, of 1 pixel 99 %.
// A point is visible when its depth d satisfies
//   d <= z_min(pixel) + max(depth_tolerance_m, depth_tolerance_ratio * d),
// z_min being the buffer's nearest depth at the point's own pixel.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::mapping {

struct VisibilityOptions {
  // Half size of the z-buffer splat in pixels, each in [-1, 32]; -1: automatic, per point (see above).
  int splat_half_width_px = -1;
  int splat_half_height_px = -1;
  int max_automatic_half_size_px = 3;   // in [0, 32]: cap of the automatic splat (see below)
  double depth_tolerance_m = 0.1;       // >= 0, finite
  double depth_tolerance_ratio = 0.02;  // in [0, 1): relative part of the tolerance
};

// The first bad field as "<prefix>.field: must be ..., got value"; ok otherwise.
Status ValidateVisibilityOptions(const VisibilityOptions& options, const std::string& prefix = "visibility");

enum class PointVisibility : std::uint8_t {
  kOutside,   // behind the camera, beyond the distortion model's valid region, or outside the image
  kOccluded,  // inside the image but behind a nearer surface
  kVisible,
};

struct ProjectedPoint {
  Eigen::Vector2f pixel = Eigen::Vector2f::Zero();  // pixel coordinates (centre of top-left pixel = 0, 0)
  float depth = 0;                                  // z in the camera frame, m
  float off_axis_tan = 0;  // tan of the angle between the ray and the optical axis: |(x, y)| / z
  PointVisibility visibility = PointVisibility::kOutside;
};

struct ProjectedScan {
  std::vector<ProjectedPoint> points;  // one per input point, same order
  std::size_t in_image = 0;            // points not kOutside
  std::size_t visible = 0;
};

// Projects the points and runs the occlusion test. Non-finite points are kOutside.
ProjectedScan ProjectWithOcclusion(std::span<const Eigen::Vector3f> points_world, const CameraModel& camera,
                                   const SE3& T_world_cam, const VisibilityOptions& options);

}  // namespace uf::mapping
