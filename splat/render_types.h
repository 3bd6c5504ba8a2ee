// What a splat renderer takes and gives: a pinhole camera with its pose, the rendering rules shared by the
// Vulkan renderer and the CPU reference, and the rendered view.
//
// Camera axes as OpenCV: x right, y down, z forward; a camera-frame point t projects to
// (u, v) = (fx t_x/t_z + cx, fy t_y/t_z + cy), and pixel (x, y) is sampled at (u, v) = (x, y) (the OpenCV
// convention, pixel centres at integer coordinates, which is also where 3DGS samples).
//
// Rendering rules (3DGS, Kerbl et al. 2023), identical in every renderer:
//  1. Projection (EWA): t = R_cw mu + t_cw; Gaussians with t_z < near are culled. J is the Jacobian of the
//     projection at t, with t_x/t_z, t_y/t_z clamped to 1.3x the half field of view; Sigma_2D = J W Sigma W^T
//     J^T + low_pass I (low_pass = 0.3 px^2 dilation). The conic is Sigma_2D^-1; the radius is
//     ceil(3 sqrt(lambda_max(Sigma_2D))) px; Gaussians with a zero-area footprint or off-screen are culled.
//  2. Colour from SH at the direction d = (mu - camera centre) / |mu - camera centre|, plus 0.5, clamped >=
//  0.
//  3. A Gaussian with projected mean (u, v) and radius r touches the tiles (kTileSize px square) with
//     tile x in [clamp(int((u - r) / 16)), clamp(int((u + r + 15) / 16))) (int() truncates; clamp to
//     [0, tiles_x]), likewise in y; it contributes only to pixels inside those tiles. No tile: culled.
//  4. Per pixel, front-to-back in increasing t_z (ties: lower Gaussian index first):
//       alpha = min(max_alpha, opacity exp(-0.5 d^T conic d)), d = pixel - mean_2D; skip if alpha <
//       min_alpha; stop before a Gaussian that would bring the transmittance T below transmittance_cutoff; C
//       += T alpha colour, D += T alpha t_z, T *= (1 - alpha).
//     Final: rgb = C + T background, alpha = 1 - T, expected depth = D / alpha (inf where alpha <
//     1e-4), depth Z = t_z of the Gaussian at which the accumulated alpha first reaches 0.5 (inf if never).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "odometry/types/pinhole_intrinsics.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::splat {

struct SplatCamera {
  PinholeIntrinsics pinhole;  // image size, fx, fy, cx, cy
  SE3 T_world_camera;         // camera (OpenCV axes) -> world

  Status Validate() const;  // positive size (<= 16384) and focal lengths, finite values
};

struct RenderSettings {
  Eigen::Vector3f background = Eigen::Vector3f::Zero();
  float near = 0.2f;                    // m; Gaussians closer to the camera plane are culled
  float low_pass = 0.3f;                // px^2 added to the 2D covariance diagonal
  float min_alpha = 1.0f / 255.0f;      // contributions below are skipped
  float max_alpha = 0.99f;              // a single Gaussian never makes a pixel fully opaque
  float transmittance_cutoff = 1e-4f;   // stop blending when T would drop below
  static constexpr int kTileSize = 16;  // px
};

// Row-major images, pixel (x, y) at index y * width + x.
struct RenderedView {
  int width = 0, height = 0;
  std::vector<float> rgb;             // 3 per pixel, display-referred (see gaussian_model.h)
  std::vector<float> alpha;           // 1 - final transmittance
  std::vector<float> depth;           // Z: median depth (rule 4), inf where never reached
  std::vector<float> expected_depth;  // alpha-weighted mean t_z, inf where alpha < 1e-4
  static constexpr float kNoDepth = std::numeric_limits<float>::infinity();

  // A view of width x height with every channel allocated: rgb and alpha 0, both depths kNoDepth.
  static RenderedView Sized(int width, int height);
};

// Checks the settings (near > 0, 0 <= min_alpha < max_alpha <= 1, cutoff in [0, 1), low_pass >= 0, finite
// background); the message names the field and value.
Status ValidateRenderSettings(const RenderSettings& settings);

}  // namespace uf::splat
