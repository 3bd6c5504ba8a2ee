// CPU reference splat renderer: a slow, straightforward implementation of the rendering rules in
// splat/render_types.h. It is the specification the Vulkan shaders are tested against, so it computes in
// float in the same order as the shaders and favours clarity over speed (per pixel: gather, sort, blend).
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "splat/gaussian_model.h"
#include "splat/render_types.h"

namespace uf::splat {

// The camera as the renderers use it, in float: T_camera_world = T_world_camera^-1 (computed in double,
// then rounded), the camera centre in the world and the pinhole intrinsics. The Vulkan renderer uploads
// exactly these values (vk/frame_params.h, the shaders' FrameParams), so both renderers start from the same
// floats. That is why it keeps its own float fx, fy, cx, cy, width, height rather than the double
// PinholeIntrinsics of SplatCamera (odometry/types/pinhole_intrinsics.h): it is their rounding to the
// shaders' precision.
struct FloatCamera {
  Eigen::Matrix3f R_camera_world;
  Eigen::Vector3f t_camera_world;
  Eigen::Vector3f centre_world;  // camera centre = translation of T_world_camera
  float fx, fy, cx, cy;
  float tan_half_fov_x, tan_half_fov_y;  // width / (2 fx), height / (2 fy)
  int width, height;
  int tiles_x, tiles_y;  // ceil(size / kTileSize)
};
FloatCamera MakeFloatCamera(const SplatCamera& camera);

// One Gaussian projected into the image (rules 1-3).
struct ProjectedGaussian {
  bool culled = true;                                 // behind the near plane, no area, or no tile
  Eigen::Vector2f mean_2d = Eigen::Vector2f::Zero();  // (u, v), px
  Eigen::Vector3f conic = Eigen::Vector3f::Zero();  // Sigma_2D^-1 = [[a, b], [b, c]] stored (a, b, c), px^-2
  int radius = 0;                                   // ceil(3 sqrt(lambda_max(Sigma_2D))), px
  float depth = 0;                                  // t_z, m
  Eigen::Vector3f color = Eigen::Vector3f::Zero();  // SH colour + 0.5, clamped >= 0
  float opacity = 0;                                // sigmoid(opacity logit)
  Eigen::Vector2i tile_min = Eigen::Vector2i::Zero();  // touched tiles: [tile_min, tile_max) in x and y
  Eigen::Vector2i tile_max = Eigen::Vector2i::Zero();
};

ProjectedGaussian ProjectGaussian(const GaussianModel& model, std::size_t index, const FloatCamera& camera,
                                  const RenderSettings& settings);

// Renders the model (rule 4 per pixel). The model must be valid (GaussianModel::Validate) and the camera
// too (SplatCamera::Validate); both are asserted.
RenderedView RenderReference(const GaussianModel& model, const SplatCamera& camera,
                             const RenderSettings& settings);

}  // namespace uf::splat
