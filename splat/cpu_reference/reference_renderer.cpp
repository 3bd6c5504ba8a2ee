#include "splat/cpu_reference/reference_renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

#include "splat/cpu_reference/spherical_harmonics.h"

namespace uf::splat {

namespace {

constexpr int kTile = RenderSettings::kTileSize;

int CeilDiv(int a, int b) { return (a + b - 1) / b; }

// Rule 3: tile index range of a footprint [centre - r, centre + r] along one axis; int() truncates
// (towards zero), clamped to [0, tiles]. Clamping the float first gives the same result and keeps the
// conversion defined for any value.
int TileBound(float position_px, int tiles) {
  return static_cast<int>(
      std::clamp(position_px / static_cast<float>(kTile), 0.0f, static_cast<float>(tiles)));
}

}  // namespace

FloatCamera MakeFloatCamera(const SplatCamera& camera) {
  const SE3 T_camera_world = camera.T_world_camera.inverse();
  FloatCamera c;
  c.R_camera_world = T_camera_world.rotation().cast<float>();
  c.t_camera_world = T_camera_world.translation().cast<float>();
  c.centre_world = camera.T_world_camera.translation().cast<float>();
  const PinholeIntrinsics& pinhole = camera.pinhole;
  c.fx = static_cast<float>(pinhole.fx);
  c.fy = static_cast<float>(pinhole.fy);
  c.cx = static_cast<float>(pinhole.cx);
  c.cy = static_cast<float>(pinhole.cy);
  c.tan_half_fov_x = 0.5f * static_cast<float>(pinhole.width) / c.fx;
  c.tan_half_fov_y = 0.5f * static_cast<float>(pinhole.height) / c.fy;
  c.width = pinhole.width;
  c.height = pinhole.height;
  c.tiles_x = CeilDiv(pinhole.width, kTile);
  c.tiles_y = CeilDiv(pinhole.height, kTile);
  return c;
}

ProjectedGaussian ProjectGaussian(const GaussianModel& model, std::size_t index, const FloatCamera& camera,
                                  const RenderSettings& settings) {
  ProjectedGaussian g;
  const Eigen::Vector3f& mu = model.positions[index];
  // Rule 1: the mean in the camera frame, t = R_cw mu + t_cw; cull in front of the near plane.
  const Eigen::Vector3f t = camera.R_camera_world * mu + camera.t_camera_world;
  if (t.z() < settings.near) return g;

  // 3D covariance Sigma = R S S^T R^T, S = diag(exp(log_scale)), R from the normalized quaternion.
  const Eigen::Matrix3f R = model.rotations[index].normalized().toRotationMatrix();
  const Eigen::Vector3f s = model.log_scales[index].array().exp();
  const Eigen::Matrix3f M = R * s.asDiagonal();
  const Eigen::Matrix3f sigma = M * M.transpose();

  // EWA: J = d(u, v)/dt at t with t_x/t_z, t_y/t_z clamped to 1.3x the half field of view:
  //   J = [[fx/t_z, 0, -fx t_x/t_z^2], [0, fy/t_z, -fy t_y/t_z^2]];  Sigma_2D = J W Sigma W^T J^T + low_pass
  //   I.
  const float lim_x = 1.3f * camera.tan_half_fov_x, lim_y = 1.3f * camera.tan_half_fov_y;
  const float tx = std::clamp(t.x() / t.z(), -lim_x, lim_x) * t.z();
  const float ty = std::clamp(t.y() / t.z(), -lim_y, lim_y) * t.z();
  Eigen::Matrix<float, 2, 3> J;
  J << camera.fx / t.z(), 0.0f, -camera.fx * tx / (t.z() * t.z()),  //
      0.0f, camera.fy / t.z(), -camera.fy * ty / (t.z() * t.z());
  const Eigen::Matrix<float, 2, 3> T = J * camera.R_camera_world;
  const Eigen::Matrix2f sigma_2d = T * sigma * T.transpose();
  const float a = sigma_2d(0, 0) + settings.low_pass, b = sigma_2d(0, 1),
              c = sigma_2d(1, 1) + settings.low_pass;

  // Conic = Sigma_2D^-1; radius from the largest eigenvalue mid + sqrt(mid^2 - det).
  const float det = a * c - b * b;
  if (!(det > 0.0f)) return g;
  const float mid = 0.5f * (a + c);
  const float lambda_max = mid + std::sqrt(std::max(0.0f, mid * mid - det));
  const int radius = static_cast<int>(std::ceil(3.0f * std::sqrt(lambda_max)));
  if (radius <= 0) return g;

  const float u = camera.fx * t.x() / t.z() + camera.cx;
  const float v = camera.fy * t.y() / t.z() + camera.cy;
  // Rule 3: the touched tiles; none means off-screen.
  const float r = static_cast<float>(radius);
  g.tile_min = {TileBound(u - r, camera.tiles_x), TileBound(v - r, camera.tiles_y)};
  g.tile_max = {TileBound(u + r + (kTile - 1), camera.tiles_x),
                TileBound(v + r + (kTile - 1), camera.tiles_y)};
  if (g.tile_min.x() >= g.tile_max.x() || g.tile_min.y() >= g.tile_max.y()) return g;

  // Rule 2: colour from SH at the viewing direction, + 0.5, clamped >= 0.
  const Eigen::Vector3f direction = (mu - camera.centre_world).normalized();
  const float* coefficients = model.sh.data() + index * static_cast<std::size_t>(model.ShStride());
  g.color = (EvaluateSh(model.sh_degree, coefficients, direction).array() + 0.5f).max(0.0f);

  g.culled = false;
  g.mean_2d = {u, v};
  g.conic = {c / det, -b / det, a / det};
  g.radius = radius;
  g.depth = t.z();
  g.opacity = 1.0f / (1.0f + std::exp(-model.opacity_logits[index]));
  return g;
}

RenderedView RenderReference(const GaussianModel& model, const SplatCamera& camera,
                             const RenderSettings& settings) {
  assert(model.Validate().ok() && camera.Validate().ok());
  const FloatCamera fc = MakeFloatCamera(camera);
  std::vector<ProjectedGaussian> projected(model.size());
  for (std::size_t i = 0; i < model.size(); ++i) projected[i] = ProjectGaussian(model, i, fc, settings);

  RenderedView view = RenderedView::Sized(camera.pinhole.width, camera.pinhole.height);

  std::vector<std::size_t> list;
  for (int y = 0; y < camera.pinhole.height; ++y) {
    for (int x = 0; x < camera.pinhole.width; ++x) {
      // Gather the Gaussians whose tile rectangle holds this pixel's tile, sorted by (t_z, index).
      const int tile_x = x / kTile, tile_y = y / kTile;
      list.clear();
      for (std::size_t i = 0; i < projected.size(); ++i) {
        const ProjectedGaussian& g = projected[i];
        if (!g.culled && tile_x >= g.tile_min.x() && tile_x < g.tile_max.x() && tile_y >= g.tile_min.y() &&
            tile_y < g.tile_max.y())
          list.push_back(i);
      }
      std::stable_sort(list.begin(), list.end(),
                       [&](std::size_t i, std::size_t j) { return projected[i].depth < projected[j].depth; });

      // Rule 4: front-to-back alpha blending.
      float T = 1.0f, D = 0.0f, median = RenderedView::kNoDepth;
      Eigen::Vector3f C = Eigen::Vector3f::Zero();
      for (const std::size_t i : list) {
        const ProjectedGaussian& g = projected[i];
        const float dx = static_cast<float>(x) - g.mean_2d.x(), dy = static_cast<float>(y) - g.mean_2d.y();
        // power = -0.5 d^T conic d, written as in the rasterizer shader.
        const float power = -0.5f * (g.conic.x() * dx * dx + g.conic.z() * dy * dy) - g.conic.y() * dx * dy;
        const float alpha = std::min(settings.max_alpha, g.opacity * std::exp(power));
        if (alpha < settings.min_alpha) continue;
        const float next_T = T * (1.0f - alpha);
        if (next_T < settings.transmittance_cutoff) break;
        const float weight = T * alpha;
        C += weight * g.color;
        D += weight * g.depth;
        T = next_T;
        // Median depth: the first Gaussian after which the accumulated alpha 1 - T reaches 0.5.
        if (median == RenderedView::kNoDepth && T <= 0.5f) median = g.depth;
      }
      const std::size_t p = static_cast<std::size_t>(y) * camera.pinhole.width + x;
      const Eigen::Vector3f rgb = C + T * settings.background;
      for (int c = 0; c < 3; ++c) view.rgb[3 * p + c] = rgb[c];
      const float alpha = 1.0f - T;
      view.alpha[p] = alpha;
      view.depth[p] = median;
      view.expected_depth[p] = alpha < 1e-4f ? RenderedView::kNoDepth : D / alpha;
    }
  }
  return view;
}

}  // namespace uf::splat
