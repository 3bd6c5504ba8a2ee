// Camera images made into splat training images: 8-bit to float rgb, lens distortion removed, resized to the
// training resolution with the intrinsics to match, and LiDAR depth rendered into the view. The training and
// held-out views of splat training are made with these (docs/ARCHITECTURE.md, the splat stage).
//
// Pixel convention (splat/render_types.h, odometry/types/camera_model.h): pixel (x, y) is centred at (x, y),
// so pixel x covers [x - 0.5, x + 0.5]. Resizing by s = W'/W keeps the image's edges where they are: an image
// coordinate u becomes u' = s (u + 0.5) - 0.5, hence fx' = s fx and cx' = s (cx + 0.5) - 0.5 (likewise y with
// s_y = H'/H). Down-scaling averages the source pixels over each target pixel's footprint, weighted by the
// area they overlap (box filter, exact for any ratio); up-scaling thereby picks the covering pixel.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "odometry/types/camera_model.h"
#include "odometry/types/measurements.h"
#include "splat/render_types.h"
#include "splat/training/training_options.h"

namespace uf::splat {

// width x height x 3 floats in [0, 1] (v / 255) of an 8-bit gray (replicated) or RGB image.
std::vector<float> ToRgbFloat(const Image& image);

// The view through `pinhole` (same camera centre and axes) of an image taken through `model`: pixel p of
// the result has the ray b = ((p_x - cx) / fx, (p_y - cy) / fy, 1), sampled bilinearly at model.Project(b)
// (clamped to the image's edge pixels); rays the model cannot project or that land outside the image are 0.
std::vector<float> Undistort(std::span<const float> rgb, const CameraModel& model,
                             const PinholeIntrinsics& pinhole);

// Which pixels of Undistort's result the image fills: pinhole.width x pinhole.height, 1 where the ray
// lands inside the image, 0 where Undistort leaves 0 for want of a source pixel.
std::vector<std::uint8_t> UndistortedCoverage(const CameraModel& model, const PinholeIntrinsics& pinhole);

// A mask (1: use, 0: masked) of width x height resized to new_width x new_height: a target pixel is used
// only when every source pixel its footprint overlaps is (area weights as ResizeArea).
std::vector<std::uint8_t> ResizeMask(std::span<const std::uint8_t> mask, int width, int height, int new_width,
                                     int new_height);

// Area-weighted resize of a width x height x channels image (see the top of this file).
std::vector<float> ResizeArea(std::span<const float> image, int width, int height, int channels,
                              int new_width, int new_height);

// The pinhole for an image resized to width x height (see the top of this file).
PinholeIntrinsics ScalePinhole(const PinholeIntrinsics& pinhole, int width, int height);

// Per-pixel depth (0: none) of width x height resized to new_width x new_height as ProjectDepth would have
// rendered it at that size: each source pixel's centre u lands in the target pixel round(s (u + 0.5) - 0.5),
// which keeps the nearest depth landing in it.
std::vector<float> ResizeDepth(std::span<const float> depth, int width, int height, int new_width,
                               int new_height);

// A training view at another size: rgb by ResizeArea, depth by ResizeDepth, mask by ResizeMask, the
// intrinsics by ScalePinhole; the pose is kept.
TrainingView ResizeView(const TrainingView& view, int width, int height);

// LiDAR depth for a view: each point t = T_camera_world p in front of the camera (t_z > near) lands in the
// pixel (round(fx t_x / t_z + cx), round(fy t_y / t_z + cy)); a pixel keeps the nearest t_z (a z-buffer).
// width x height floats, 0 where no point landed.
std::vector<float> ProjectDepth(std::span<const Eigen::Vector3f> points, const SplatCamera& camera,
                                float near = 0.2f);

}  // namespace uf::splat
