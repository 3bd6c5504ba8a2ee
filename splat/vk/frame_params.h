// The per-frame parameter block of the splat shaders, byte for byte the std430 FrameParams struct of
// shaders/frame_params.glsl (11 x 16 bytes), filled from the float camera the CPU reference uses too.
#pragma once

#include <cstdint>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/render_types.h"

namespace uf::splat::vk {

struct FrameParams {
  float R_row0[4], R_row1[4], R_row2[4];  // rows of R_camera_world
  float t_camera_world[4];
  float centre_world[4];
  float intrinsics[4];      // fx, fy, cx, cy
  float limits[4];          // tan_half_fov_x, tan_half_fov_y, near, low_pass
  float blend[4];           // min_alpha, max_alpha, transmittance_cutoff, 0
  float background[4];      // rgb, 0
  std::int32_t size[4];     // width, height, tiles_x, tiles_y
  std::uint32_t counts[4];  // num_gaussians, sh_degree, pair_capacity, active SH degree (<= sh_degree)
};
static_assert(sizeof(FrameParams) == 11 * 16, "must match shaders/frame_params.glsl");

// active_sh_degree: the SH bands evaluated (those above count as zero); < 0 or > sh_degree: sh_degree.
inline FrameParams MakeFrameParams(const FloatCamera& camera, const RenderSettings& settings,
                                   std::uint32_t num_gaussians, int sh_degree, std::uint32_t pair_capacity,
                                   int active_sh_degree = -1) {
  FrameParams p{};
  for (int c = 0; c < 3; ++c) {
    p.R_row0[c] = camera.R_camera_world(0, c);
    p.R_row1[c] = camera.R_camera_world(1, c);
    p.R_row2[c] = camera.R_camera_world(2, c);
    p.t_camera_world[c] = camera.t_camera_world[c];
    p.centre_world[c] = camera.centre_world[c];
    p.background[c] = settings.background[c];
  }
  p.intrinsics[0] = camera.fx;
  p.intrinsics[1] = camera.fy;
  p.intrinsics[2] = camera.cx;
  p.intrinsics[3] = camera.cy;
  p.limits[0] = camera.tan_half_fov_x;
  p.limits[1] = camera.tan_half_fov_y;
  p.limits[2] = settings.near;
  p.limits[3] = settings.low_pass;
  p.blend[0] = settings.min_alpha;
  p.blend[1] = settings.max_alpha;
  p.blend[2] = settings.transmittance_cutoff;
  p.size[0] = camera.width;
  p.size[1] = camera.height;
  p.size[2] = camera.tiles_x;
  p.size[3] = camera.tiles_y;
  p.counts[0] = num_gaussians;
  p.counts[1] = static_cast<std::uint32_t>(sh_degree);
  p.counts[2] = pair_capacity;
  p.counts[3] = static_cast<std::uint32_t>(
      active_sh_degree < 0 || active_sh_degree > sh_degree ? sh_degree : active_sh_degree);
  return p;
}

}  // namespace uf::splat::vk
