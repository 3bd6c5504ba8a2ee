// CPU reference of one Adam step of splat training (the specification shaders/adam_step.comp is tested
// against): the update of optimizer_state.h's AdamStep on every parameter of every Gaussian, plus the 3DGS
// densification statistics of the Gaussians seen in the view.
#pragma once

#include <cstdint>
#include <vector>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/training/optimizer_state.h"

namespace uf::splat {

// Applies one step to `state` (sized for the gradients' model; Consistent()). seen[i] != 0 when Gaussian i
// was seen in the view (touched a tile); radius[i] its screen radius (px) or empty (max_radius unchanged).
// For each seen Gaussian: gradient_accum += |(dL/du * ndc_scale_x, dL/dv * ndc_scale_y)|, gradient_count +=
// 1, max_radius = max(max_radius, radius). All arithmetic in float, like the shader.
void AdamStepReference(OptimizerHostState& state, const GaussianGradients& gradients,
                       const std::vector<std::uint32_t>& seen, const std::vector<float>& radius,
                       const AdamStep& step);

}  // namespace uf::splat
