#include "splat/training/adam_reference.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace uf::splat {

namespace {

// The Adam rule on one parameter (see AdamStep), in float; bias corrections c1 = 1 - b1^t, c2 = 1 - b2^t.
struct AdamRule {
  float beta1, beta2, epsilon, c1, c2;
  void Apply(float lr, float g, float& p, float& m, float& v) const {
    m = beta1 * m + (1.0f - beta1) * g;
    v = beta2 * v + (1.0f - beta2) * (g * g);
    p -= lr * (m / c1) / (std::sqrt(v / c2) + epsilon);
  }
};

}  // namespace

void AdamStepReference(OptimizerHostState& state, const GaussianGradients& gradients,
                       const std::vector<std::uint32_t>& seen, const std::vector<float>& radius,
                       const AdamStep& step) {
  assert(state.Consistent());
  const std::size_t n = state.size(), stride = static_cast<std::size_t>(state.model.ShStride());
  assert(gradients.position.size() == n && gradients.sh.size() == n * stride && seen.size() == n);
  assert(radius.empty() || radius.size() == n);
  const AdamRule rule{step.beta1, step.beta2, step.epsilon, AdamBiasCorrection(step.beta1, step.step),
                      AdamBiasCorrection(step.beta2, step.step)};
  GaussianModel& model = state.model;
  for (std::size_t i = 0; i < n; ++i) {
    float* m = state.m_geometry.data() + i * kGeometryMomentFloats;
    float* v = state.v_geometry.data() + i * kGeometryMomentFloats;
    for (int a = 0; a < 3; ++a) {
      rule.Apply(step.lr_position, gradients.position[i][a], model.positions[i][a], m[kMomentPosition + a],
                 v[kMomentPosition + a]);
      rule.Apply(step.lr_log_scale, gradients.log_scale[i][a], model.log_scales[i][a], m[kMomentLogScale + a],
                 v[kMomentLogScale + a]);
    }
    rule.Apply(step.lr_opacity, gradients.opacity_logit[i], model.opacity_logits[i], m[kMomentOpacity],
               v[kMomentOpacity]);
    // The raw quaternion w x y z (the renderer normalizes on use).
    Eigen::Quaternionf& q = model.rotations[i];
    float wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int a = 0; a < 4; ++a)
      rule.Apply(step.lr_rotation, gradients.rotation[i][a], wxyz[a], m[kMomentRotation + a],
                 v[kMomentRotation + a]);
    q = Eigen::Quaternionf(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
    // SH: coefficient k = (j / 3); DC at its own rate, the rest at lr_sh_rest, inactive bands untouched.
    for (std::size_t j = 0; j < stride; ++j) {
      const int k = static_cast<int>(j / 3);
      if (k >= step.active_sh_coefficients) continue;
      const std::size_t e = i * stride + j;
      rule.Apply(k == 0 ? step.lr_sh_dc : step.lr_sh_rest, gradients.sh[e], model.sh[e], state.m_sh[e],
                 state.v_sh[e]);
    }
    if (seen[i] == 0) continue;
    const float du = gradients.mean_2d[i].x() * step.ndc_scale_x;
    const float dv = gradients.mean_2d[i].y() * step.ndc_scale_y;
    state.gradient_accum[i] += std::sqrt(du * du + dv * dv);
    state.gradient_count[i] += 1;
    if (!radius.empty()) state.max_radius[i] = std::max(state.max_radius[i], radius[i]);
  }
}

}  // namespace uf::splat
