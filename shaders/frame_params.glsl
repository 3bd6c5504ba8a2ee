// Per-frame parameters shared by the projection, key emission and rasterization shaders (std430 storage
// buffer, written by the host each frame; mirrored by uf::splat::vk::FrameParams in splat/vk/frame_params.h).
struct FrameParams {
  vec4 R_row0;          // rows of R_camera_world (xyz), w unused
  vec4 R_row1;
  vec4 R_row2;
  vec4 t_camera_world;  // xyz: t in p_camera = R_camera_world p_world + t
  vec4 centre_world;    // xyz: camera centre in the world (SH viewing direction)
  vec4 intrinsics;      // fx, fy, cx, cy (px)
  vec4 limits;          // tan_half_fov_x, tan_half_fov_y, near (m), low_pass (px^2)
  vec4 blend;           // min_alpha, max_alpha, transmittance_cutoff, unused
  vec4 background;      // rgb, unused
  ivec4 size;           // width, height, tiles_x, tiles_y
  uvec4 counts;         // num_gaussians, sh_degree (model: SH stride), pair_capacity, active SH degree
                        // (<= sh_degree: bands above it are evaluated as zero, their gradients are zero)
};

// Counters buffer (uint array), zeroed at the start of each frame:
const uint kCounterPairs = 0;          // tile-Gaussian pairs wanted (may exceed the key capacity)
const uint kCounterVisible = 1;        // Gaussians that touch at least one tile
const uint kCounterPixelPairsLo = 2;   // pixel-Gaussian pairs evaluated by the rasterizer, low 32 bits
const uint kCounterPixelPairsHi = 3;   // and the carry
const uint kTileSize = 16;
