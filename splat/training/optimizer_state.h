// The optimizer's state on the host: the model, Adam's first and second moments of every parameter and the
// densification statistics, as downloaded from the device for densification / pruning (training/densify.h)
// and uploaded back (vk/adam_pass.h). Also AdamStep, the hyper-parameters of one Adam step (shared by the
// shader and the CPU reference, training/adam_reference.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splat/gaussian_model.h"

namespace uf::splat {

// Floats of Adam moments per Gaussian for the geometry, laid out like the device geometry (3 vec4):
// (mu xyz, opacity logit), (log_scale xyz, unused 0), (quaternion w x y z).
inline constexpr std::size_t kGeometryMomentFloats = 12;
// Offsets into those 12 floats.
inline constexpr std::size_t kMomentPosition = 0, kMomentOpacity = 3, kMomentLogScale = 4,
                             kMomentRotation = 8;

struct OptimizerHostState {
  GaussianModel model;
  // Adam moments: m (first, mean of gradients) and v (second, mean of squared gradients).
  std::vector<float> m_geometry, v_geometry;  // kGeometryMomentFloats per Gaussian (layout above)
  std::vector<float> m_sh, v_sh;  // model.ShStride() per Gaussian, coefficient-major like model.sh
  // Densification statistics since the last densification (3DGS): per Gaussian the sum over the views that
  // saw it of |dL/d(mean in NDC)|, the number of those views, and the largest screen radius (px).
  std::vector<float> gradient_accum;
  std::vector<std::uint32_t> gradient_count;
  std::vector<float> max_radius;

  std::size_t size() const { return model.size(); }
  // Every array sized for model.size() Gaussians (programmer check, for asserts and tests).
  bool Consistent() const;
  // Sizes every optimizer array for the model's size, new entries zero (existing ones kept).
  void ResizeToModel();
  // Zeros the densification statistics.
  void ResetStatistics();
};

// One Adam step (Kingma & Ba 2015) over all Gaussians, per parameter p with gradient g:
//   m = b1 m + (1 - b1) g,  v = b2 v + (1 - b2) g^2,  p -= lr (m / (1 - b1^t)) / (sqrt(v / (1 - b2^t)) +
//   eps).
struct AdamStep {
  float lr_position = 0, lr_log_scale = 0, lr_rotation = 0, lr_opacity = 0, lr_sh_dc = 0, lr_sh_rest = 0;
  float beta1 = 0.9f, beta2 = 0.999f, epsilon = 1e-15f;
  int step = 1;  // t, 1-based, for the bias corrections
  // (active degree + 1)^2: SH coefficients k >= this get no update (parameter and moments stay as they are,
  // zero), which makes rendering at the full degree equal to rendering at the active degree.
  int active_sh_coefficients = 1;
  // W / 2, H / 2: dL/d(NDC) = dL/d(pixel) * (W/2, H/2) (pixel u = ((ndc_x + 1) W - 1) / 2).
  float ndc_scale_x = 1, ndc_scale_y = 1;
};

// The bias corrections 1 - b1^t and 1 - b2^t, computed in double then rounded (shader and reference use
// these same floats).
float AdamBiasCorrection(float beta, int step);

}  // namespace uf::splat
