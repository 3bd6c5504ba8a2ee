// The per-pixel part of the CPU reference backward (rule 4 backwards), the whole backward pass and the
// expected-depth helper; declared in reference_backward.h.
#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>

#include "splat/cpu_reference/reference_backward.h"

namespace uf::splat {

namespace {

constexpr int kTile = RenderSettings::kTileSize;

// One Gaussian blended into a pixel, as the forward saw it.
struct Blended {
  std::size_t index;
  float dx, dy;        // pixel - mean_2d
  float gaussian;      // G = exp(power)
  float alpha;         // min(max_alpha, opacity G)
  bool alpha_clamped;  // opacity G > max_alpha: no gradient flows to opacity, conic or mean
  float T;             // transmittance in front of it
};

// Rule 4 forward for pixel (x, y), keeping what the backward needs.
void BlendForward(const std::vector<ProjectedGaussian>& projected, const RenderSettings& settings, int x,
                  int y, std::vector<std::size_t>* list, std::vector<Blended>* blended) {
  const int tile_x = x / kTile, tile_y = y / kTile;
  list->clear();
  blended->clear();
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const ProjectedGaussian& g = projected[i];
    if (!g.culled && tile_x >= g.tile_min.x() && tile_x < g.tile_max.x() && tile_y >= g.tile_min.y() &&
        tile_y < g.tile_max.y())
      list->push_back(i);
  }
  std::stable_sort(list->begin(), list->end(),
                   [&](std::size_t i, std::size_t j) { return projected[i].depth < projected[j].depth; });
  float T = 1.0f;
  for (const std::size_t i : *list) {
    const ProjectedGaussian& g = projected[i];
    const float dx = static_cast<float>(x) - g.mean_2d.x(), dy = static_cast<float>(y) - g.mean_2d.y();
    const float power = -0.5f * (g.conic.x() * dx * dx + g.conic.z() * dy * dy) - g.conic.y() * dx * dy;
    const float gaussian = std::exp(power);
    const float unclamped = g.opacity * gaussian;
    const float alpha = std::min(settings.max_alpha, unclamped);
    if (alpha < settings.min_alpha) continue;
    const float next_T = T * (1.0f - alpha);
    if (next_T < settings.transmittance_cutoff) break;
    blended->push_back({i, dx, dy, gaussian, alpha, unclamped > settings.max_alpha, T});
    T = next_T;
  }
}

}  // namespace

GaussianGradients GaussianGradients::Zero(const GaussianModel& model) {
  GaussianGradients g;
  const std::size_t n = model.size();
  g.position.assign(n, Eigen::Vector3f::Zero());
  g.log_scale.assign(n, Eigen::Vector3f::Zero());
  g.rotation.assign(n, Eigen::Vector4f::Zero());
  g.opacity_logit.assign(n, 0.0f);
  g.sh.assign(n * static_cast<std::size_t>(model.ShStride()), 0.0f);
  g.mean_2d.assign(n, Eigen::Vector2f::Zero());
  return g;
}

std::vector<ProjectedGaussianGradients> RasterizeReferenceBackward(
    const std::vector<ProjectedGaussian>& projected, const FloatCamera& camera,
    const RenderSettings& settings, const ViewGradients& gradients) {
  [[maybe_unused]] const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  assert(gradients.rgb.size() == 3 * pixels);
  assert(gradients.alpha.empty() || gradients.alpha.size() == pixels);
  assert(gradients.depth_sum.empty() || gradients.depth_sum.size() == pixels);
  std::vector<ProjectedGaussianGradients> out(projected.size());
  std::vector<std::size_t> list;
  std::vector<Blended> blended;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      BlendForward(projected, settings, x, y, &list, &blended);
      const std::size_t p = static_cast<std::size_t>(y) * camera.width + x;
      const Eigen::Vector3f dL_drgb(gradients.rgb[3 * p], gradients.rgb[3 * p + 1], gradients.rgb[3 * p + 2]);
      const float dL_dA = gradients.alpha.empty() ? 0.0f : gradients.alpha[p];
      const float dL_dD = gradients.depth_sum.empty() ? 0.0f : gradients.depth_sum[p];

      // With T_i the transmittance in front of blended Gaussian i (0 = front), the outputs are
      //   rgb = sum_i T_i a_i c_i + T_N bg,  A = 1 - T_N = sum_i T_i a_i,  D = sum_i T_i a_i z_i.
      // Splitting rgb at i: rgb = (front part) + T_i (a_i c_i + (1 - a_i) B_i), where B_i is what lies
      // behind i seen through T_{i+1}: B_{N-1} = bg, B_{i-1} = a_i c_i + (1 - a_i) B_i (back to front). So
      //   drgb/dc_i = T_i a_i,  drgb/da_i = T_i (c_i - B_i),
      // and likewise dA/da_i = T_i (1 - B^A_i) with B^A (bg 0, "colour" 1), dD/da_i = T_i (z_i - B^D_i)
      // with B^D (bg 0, "colour" z), dD/dz_i = T_i a_i. No division by (1 - a_i) is needed.
      Eigen::Vector3f behind_rgb = settings.background;
      float behind_A = 0.0f, behind_D = 0.0f;
      for (auto it = blended.rbegin(); it != blended.rend(); ++it) {
        const ProjectedGaussian& g = projected[it->index];
        ProjectedGaussianGradients& v = out[it->index];
        const float a = it->alpha, weight = it->T * a;
        v.color += weight * dL_drgb;
        v.depth += weight * dL_dD;
        const float dL_dalpha = it->T * (dL_drgb.dot(g.color - behind_rgb) + dL_dA * (1.0f - behind_A) +
                                         dL_dD * (g.depth - behind_D));
        behind_rgb = a * g.color + (1.0f - a) * behind_rgb;
        behind_A = a + (1.0f - a) * behind_A;
        behind_D = a * g.depth + (1.0f - a) * behind_D;
        if (it->alpha_clamped) continue;  // a = max_alpha: constant in opacity, conic and mean

        // a = o G, G = exp(power), power = -0.5 (A dx^2 + C dy^2) - B dx dy with conic (A, B, C) and
        // (dx, dy) = pixel - (u, v):
        //   da/do = G,  dpower/d(A, B, C) = (-dx^2 / 2, -dx dy, -dy^2 / 2),
        //   dpower/du = A dx + B dy,  dpower/dv = B dx + C dy   (dx = x - u, so d/du = -d/ddx).
        v.opacity += dL_dalpha * it->gaussian;
        const float dL_dpower = dL_dalpha * g.opacity * it->gaussian;
        const float dx = it->dx, dy = it->dy;
        v.conic += dL_dpower * Eigen::Vector3f(-0.5f * dx * dx, -dx * dy, -0.5f * dy * dy);
        v.mean_2d += dL_dpower * Eigen::Vector2f(g.conic.x() * dx + g.conic.y() * dy,
                                                 g.conic.y() * dx + g.conic.z() * dy);
      }
    }
  }
  return out;
}

GaussianGradients RenderReferenceBackward(const GaussianModel& model, const SplatCamera& camera,
                                          const RenderSettings& settings, const ViewGradients& gradients) {
  assert(model.Validate().ok() && camera.Validate().ok());
  const FloatCamera fc = MakeFloatCamera(camera);
  std::vector<ProjectedGaussian> projected(model.size());
  for (std::size_t i = 0; i < model.size(); ++i) projected[i] = ProjectGaussian(model, i, fc, settings);
  const std::vector<ProjectedGaussianGradients> upstream =
      RasterizeReferenceBackward(projected, fc, settings, gradients);
  GaussianGradients out = GaussianGradients::Zero(model);
  for (std::size_t i = 0; i < model.size(); ++i)
    ProjectGaussianBackward(model, i, fc, settings, upstream[i], &out);
  return out;
}

void AddExpectedDepthGradient(const RenderedView& forward, const std::vector<float>& dL_dexpected_depth,
                              ViewGradients* gradients) {
  const std::size_t pixels = static_cast<std::size_t>(forward.width) * forward.height;
  assert(dL_dexpected_depth.size() == pixels && forward.alpha.size() == pixels);
  if (gradients->alpha.empty()) gradients->alpha.assign(pixels, 0.0f);
  if (gradients->depth_sum.empty()) gradients->depth_sum.assign(pixels, 0.0f);
  for (std::size_t p = 0; p < pixels; ++p) {
    const float E = forward.expected_depth[p], A = forward.alpha[p], g = dL_dexpected_depth[p];
    if (!std::isfinite(E) || !std::isfinite(g)) continue;  // A < 1e-4: E has no value
    // E = D / A:  dE/dD = 1 / A,  dE/dA = -D / A^2 = -E / A.
    gradients->depth_sum[p] += g / A;
    gradients->alpha[p] -= g * E / A;
  }
}

}  // namespace uf::splat
