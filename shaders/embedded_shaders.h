// The SPIR-V of the splat compute shaders (shaders/*.comp), compiled by glslangValidator at build time and
// embedded in the binary, so the renderer needs no shader files at run time.
#pragma once

#include <cstdint>
#include <span>

namespace uf::splat::vk {

enum class ShaderId {
  kProjectGaussians,   // project_gaussians.comp: EWA projection, SH colour, radius, tile rectangle
  kEmitTileKeys,       // emit_tile_keys.comp: one (tile, depth) key per touched tile
  kPrefixSum,          // prefix_sum.comp: exclusive scan (3 phases)
  kRadixHistogram,     // radix_histogram.comp: per-lane digit histograms of one LSD pass
  kRadixScatter,       // radix_scatter.comp: stable scatter of one LSD pass
  kTileRanges,         // tile_ranges.comp: [begin, end) of each tile in the sorted keys
  kRasterizeForward,   // rasterize_forward.comp: front-to-back blending per tile
  kRasterizeBackward,  // rasterize_backward.comp: per-tile gradients of the blending, per tile-Gaussian pair
  kProjectBackward,    // project_backward.comp: per-Gaussian gradients of projection, SH and opacity
  kPhotometricLossMoments,       // photometric_loss_moments.comp: row blur of the SSIM moments, depth pairs
  kPhotometricLossSsim,          // photometric_loss_ssim.comp: column blur, SSIM map and its partials
  kPhotometricLossPartialsBlur,  // photometric_loss_partials_blur.comp: row blur of the SSIM partials
  kPhotometricLossGradient,      // photometric_loss_gradient.comp: column blur, dL/d(images), loss sums
  kAdamStep,           // adam_step.comp: one Adam step per chunk and the densification statistics
};

std::span<const std::uint32_t> ShaderCode(ShaderId id);

}  // namespace uf::splat::vk
