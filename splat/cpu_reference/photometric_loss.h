// CPU reference of the photometric training loss of the splat trainer and its gradient with respect to the
// rendered images (the specification the loss shaders, splat/vk/loss_pass.h, are tested against):
//
//   L = (1 - l) L1 + l (1 - SSIM) + w_d L_depth,  l = ssim_weight, w_d = depth_weight,
//   L1 = mean over pixels and channels of |r - t| (r rendered rgb, t target rgb),
//   SSIM = Ssim(r, t) of splat/training/image_metrics.h (11 x 11 Gaussian window, zero padding),
//   L_depth = mean over the pixels with target depth d > 0 and rendered alpha >= 1e-4 of |E - d| / d, E the
//             expected depth D / alpha (0 when there is no such pixel or no target depth). The error is
//             relative: a LiDAR depth projected into an image is as good as the pixel's footprint, which
//             grows with d, and a floater close to the camera (what the term is for) errs by a large
//             fraction of d while the far background's metres of slack would otherwise dominate the sum.
// The gradient goes to ViewGradients: rgb directly; the depth term through E = D / alpha to depth_sum (dL/dD)
// and alpha (AddExpectedDepthGradient). |.| has the subgradient sign(.) (0 at 0).
//
// Masked pixels (an image's pixels that show nothing to learn: outside what an undistorted camera fills, the
// car's own hood) count as rendered perfectly: r is replaced by t there, in L1 and in every SSIM window that
// covers them, so they add nothing to the loss, their gradient is 0, they have no depth pair, and n stays
// 3 x width x height. On the device the mask travels as a negative target depth (vk/loss_pass.h).
#pragma once

#include <cstdint>
#include <vector>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/render_types.h"

namespace uf::splat {

struct PhotometricLossWeights {
  float ssim_weight = 0.2f;   // l above, in [0, 1]
  float depth_weight = 0.0f;  // w_d above, >= 0
};

// The terms of the loss: total is the weighted sum, l1, dssim = 1 - SSIM and depth are before weighting.
struct PhotometricLossValue {
  double total = 0, l1 = 0, dssim = 0, depth = 0;
};

struct PhotometricLoss {
  double total = 0, l1 = 0, dssim = 0, depth = 0;  // as PhotometricLossValue
  ViewGradients gradients;                         // rgb, alpha and depth_sum all sized (zeros where none)
};

// The loss of `rendered` (rgb, alpha, expected_depth used) against target_rgb (width x height x 3) and
// target_depth (width x height, 0: no depth; or empty: no depth term); mask (width x height, 0: masked; or
// empty: none). Sizes must match (asserted).
PhotometricLoss EvaluatePhotometricLoss(const RenderedView& rendered, const std::vector<float>& target_rgb,
                                        const std::vector<float>& target_depth,
                                        const PhotometricLossWeights& weights,
                                        const std::vector<std::uint8_t>& mask = {});

}  // namespace uf::splat
