// Colorization of world-frame LiDAR points from time-aligned camera images: each point is projected into
// every image (camera model with distortion, camera pose at the image's mid-exposure time), tested for
// occlusion with a z-buffer (colorize_projection.h) and given the bilinearly sampled sRGB colour of the
// image it is best seen in. Points behind every camera, outside every image or hidden in every image stay
// uncoloured.
//
// Choice among several images: the one whose mid-exposure time is closest to the point's time (the scene
// is assumed static, but parked cars move and the pose is best near the keyframe); among images with the
// same time (a rig triggered together), the one where the point lies closest to the optical axis (the most
// frontal view: least distortion, vignetting and blur). Images farther in time than max_time_difference_s
// are not used for that point.
//
// The caller computes each image's T_world_cam = T_world_body(t_image + time offset) * T_body_cam from the
// trajectory, the camera extrinsic and the camera's time offset.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mapping/colorize_projection.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::mapping {

// One image to take colours from. The image and the camera are referenced: they must outlive the call.
struct CameraView {
  const Image* image = nullptr;         // 8-bit gray or RGB, of the camera model's size
  const CameraModel* camera = nullptr;  // intrinsics and distortion
  SE3 T_world_cam;                      // camera pose at mid-exposure (OpenCV axes)
  Stamp stamp = 0;                      // mid-exposure time, ns
};

struct ColorizerOptions {
  VisibilityOptions visibility;        // z-buffer splat and depth tolerance
  double max_time_difference_s = 0.5;  // > 0: an image this far (s) from a point's time does not colour it
};

// The first bad field, e.g. "colorizer.visibility.depth_tolerance_m: must be finite and >= 0, got -1".
Status ValidateColorizerOptions(const ColorizerOptions& options);

using Rgb = std::array<std::uint8_t, 3>;  // sRGB, 8 bits per channel

struct ColorizeResult {
  std::vector<std::optional<Rgb>> colors;  // one per point; nullopt: uncoloured
  std::vector<int> view_index;             // one per point: the view it took its colour from, -1 if none
  // Counts over points (each counted once whatever the number of views), within the time limit:
  std::size_t in_footprint = 0;  // in front of a camera and inside its image
  std::size_t colored = 0;       // of those, visible in at least one image
  std::size_t occluded = 0;      // in_footprint - colored: hidden in every image whose footprint holds them
};

// Colours `points_world`; `point_stamps` holds one stamp per point or a single stamp for all of them.
// Errors: options invalid, or a view whose image is empty, not gray/RGB, or not the camera model's size.
Expected<ColorizeResult> Colorize(std::span<const Eigen::Vector3f> points_world,
                                  std::span<const Stamp> point_stamps, std::span<const CameraView> views,
                                  const ColorizerOptions& options = {});

// The colour of `image` at a pixel coordinate (pixel centres are integers), bilinear between the four
// nearest pixel centres, clamped at the border; gray images give R = G = B. Channels in [0, 255].
Eigen::Vector3f SampleBilinear(const Image& image, const Eigen::Vector2f& pixel);

// The error a view gives Colorize (empty image, wrong channels, size differing from the camera), or ok.
Status CheckCameraView(const CameraView& view);

}  // namespace uf::mapping
