// Exposure compensation for splat training on real images. A camera with automatic exposure and white
// balance records the same surface brighter or darker, and tinted, from one frame to the next; splats fitted
// to such images bake the changes into view-dependent colour and floaters, and a held-out frame is scored
// against the wrong brightness. Each image i is modelled per channel c as
//
//   t = g_c r + b_c,
//
// r the splats' rendering in one canonical exposure, t the image. Training alternates (block coordinate
// descent): the splats take a step towards the compensated image (t - b) / g, and (g, b) is then refitted to
// the image against the render of that step, by the weighted least squares
//
//   min over (g, b) of  sum_p w_p (g r_p + b - t_p)^2 + lambda W ((g - 1)^2 + b^2),   W = sum_p w_p,
//
// whose normal equations are the 2 x 2 system
//   [ S_rr + lambda W   S_r          ] [g]   [ S_rt + lambda W ]
//   [ S_r               W + lambda W ] [b] = [ S_t             ],   S_xy = sum_p w_p x_p y_p, S_x = sum w x.
// The prior (lambda = prior_weight) pulls each image towards (1, 0); it also fixes the gauge, since the
// splats' brightness and every image's gain could otherwise drift together. The weights w_p are Huber's
// (1 within huber_delta of the fit, huber_delta / |residual| beyond), by a few reweighted solves, so that
// moving objects and what the splats do not render yet count less; pixels whose image value is clipped
// (0 or 1 in 8 bits) follow no affine law and are left out.
//
// Held-out images were never trained on, so their exposure is not fitted: it is interpolated in time between
// the training images before and after them (InterpolateExposure). Automatic exposure changes smoothly along
// a drive, which is what this relies on; a frame with an abrupt change is scored against its neighbours'.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "odometry/types/stamp.h"

namespace uf::splat {

struct Exposure {
  std::array<float, 3> gain = {1, 1, 1};  // g per channel
  std::array<float, 3> bias = {0, 0, 0};  // b per channel
};

struct ExposureFitOptions {
  double prior_weight = 0.01;  // lambda above
  double huber_delta = 0.05;   // residual (image value units) beyond which a pixel's weight falls
  int reweightings = 3;        // solves after the first
  float min_gain = 0.25f, max_gain = 4.0f, max_abs_bias = 0.5f;  // the fit is clamped to these
};

// The exposure that maps `rendered` onto `image` (both width x height x 3, row-major, image in [0, 1];
// sizes must match, asserted), over the pixels `mask` keeps (one per pixel, 0: left out; empty: all).
// Without usable pixels in a channel, that channel is (1, 0).
Exposure FitExposure(std::span<const float> rendered, std::span<const float> image,
                     const ExposureFitOptions& options = {}, std::span<const std::uint8_t> mask = {});

// rgb <- g rgb + b: a canonical render as the image's exposure would show it.
void ApplyExposure(const Exposure& exposure, std::span<float> rgb);
// rgb <- (rgb - b) / g: an image brought to the canonical exposure (the training target).
void RemoveExposure(const Exposure& exposure, std::span<float> rgb);

// The exposure at `stamp` from those of the training images (stamps ascending, same length as exposures):
// linear in time between the two that bracket it, the nearest one outside their span, (1, 0) without any.
Exposure InterpolateExposure(std::span<const Stamp> stamps, std::span<const Exposure> exposures, Stamp stamp);

}  // namespace uf::splat
