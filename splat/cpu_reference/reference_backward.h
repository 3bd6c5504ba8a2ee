// CPU reference BACKWARD pass of the splat renderer: the exact gradients of RenderReference (the rules in
// splat/render_types.h) with respect to every GaussianModel parameter, for a loss L whose gradients with
// respect to the rendered images are given. Slow and straightforward like the forward; it is the
// specification the backward shaders are tested against, split the same way:
//   RasterizeReferenceBackward   per pixel, back to front: dL/d(image) -> dL/d(projected Gaussian)
//   ProjectGaussianBackward      per Gaussian: dL/d(projected Gaussian) -> dL/d(model parameters)
//   RenderReferenceBackward      both, recomputing the forward (projection and per-pixel lists).
//
// Depth: the differentiable depth quantity is the alpha-weighted depth SUM D = sum_i T_i a_i t_z,i (what
// a LiDAR depth loss needs; the median depth Z is piecewise constant and has no useful gradient). The
// expected depth E = D / alpha is a quotient of two differentiable images; AddExpectedDepthGradient turns
// dL/dE into dL/dD and dL/dalpha.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/gaussian_model.h"
#include "splat/render_types.h"

namespace uf::splat {

// dL/d(rendered images), row-major like RenderedView (pixel (x, y) at index y * width + x).
struct ViewGradients {
  std::vector<float> rgb;        // 3 per pixel (required)
  std::vector<float> alpha;      // 1 per pixel, or empty (no alpha term)
  std::vector<float> depth_sum;  // dL/dD per pixel, D = sum T a t_z (= expected_depth * alpha), or empty
};

// dL/d(one projected Gaussian), the quantities of ProjectedGaussian that the rasterizer reads.
struct ProjectedGaussianGradients {
  Eigen::Vector2f mean_2d = Eigen::Vector2f::Zero();  // dL/d(u, v), px^-1
  Eigen::Vector3f conic = Eigen::Vector3f::Zero();    // dL/d(a, b, c) of the stored conic (b once, not twice)
  float depth = 0;                                    // dL/dt_z (through D only)
  Eigen::Vector3f color = Eigen::Vector3f::Zero();    // dL/d(clamped colour)
  float opacity = 0;                                  // dL/d(sigmoid(logit))
};

// dL/d(model parameters), one entry per Gaussian, laid out like GaussianModel.
struct GaussianGradients {
  std::vector<Eigen::Vector3f> position;   // dL/dmu, world frame
  std::vector<Eigen::Vector3f> log_scale;  // dL/dln(sigma)
  std::vector<Eigen::Vector4f> rotation;   // dL/d(w, x, y, z) of the stored, UNnormalized quaternion
  std::vector<float> opacity_logit;
  std::vector<float> sh;  // coefficient-major like GaussianModel::sh
  // dL/d(u, v) of the projected mean (px^-1), summed over pixels: 3DGS densification accumulates its norm.
  std::vector<Eigen::Vector2f> mean_2d;

  // Zero gradients for a model of this size and SH degree.
  static GaussianGradients Zero(const GaussianModel& model);
};

// Per pixel, the Gaussians blended in the forward order (rule 4, minus the skipped ones and the one that
// stopped the loop) back to front, accumulated into one entry per projected Gaussian (culled ones get 0).
// gradients.rgb must have 3 * width * height entries; alpha and depth_sum are empty or width * height.
std::vector<ProjectedGaussianGradients> RasterizeReferenceBackward(
    const std::vector<ProjectedGaussian>& projected, const FloatCamera& camera,
    const RenderSettings& settings, const ViewGradients& gradients);

// Chains dL/d(projected Gaussian `index`) through rules 1-2 and ADDS the result to entry `index` of
// `gradients` (which must be sized for the model). A culled Gaussian adds nothing.
void ProjectGaussianBackward(const GaussianModel& model, std::size_t index, const FloatCamera& camera,
                             const RenderSettings& settings, const ProjectedGaussianGradients& upstream,
                             GaussianGradients* gradients);

// The gradients of L(RenderReference(model, camera, settings)) given dL/d(images). Model and camera must be
// valid (asserted), like for RenderReference.
GaussianGradients RenderReferenceBackward(const GaussianModel& model, const SplatCamera& camera,
                                          const RenderSettings& settings, const ViewGradients& gradients);

// Expected depth E = D / A (A = alpha) where A >= 1e-4 (rule 4), else no value and no gradient:
//   dL/dD += dL/dE / A,  dL/dA += -dL/dE D / A^2 = -dL/dE E / A.
// Sizes the alpha and depth_sum vectors of `gradients` if they are empty. Non-finite dL/dE entries are
// treated as zero (pixels without a depth value).
void AddExpectedDepthGradient(const RenderedView& forward, const std::vector<float>& dL_dexpected_depth,
                              ViewGradients* gradients);

}  // namespace uf::splat
