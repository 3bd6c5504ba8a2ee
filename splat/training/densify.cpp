#include "splat/training/densify.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <random>
#include <vector>

namespace uf::splat {

namespace {

// A Gaussian to add: a copy of `parent` with its mean at `position` and log-scale offset by
// `log_scale_delta`.
struct NewGaussian {
  std::size_t parent;
  Eigen::Vector3f position;
  float log_scale_delta;
};

// Appends Gaussian i of `from` to `to`, with its moments and statistics, or with them zero (a new Gaussian).
void Append(const OptimizerHostState& from, std::size_t i, bool keep_optimizer_state,
            OptimizerHostState& to) {
  const std::size_t stride = static_cast<std::size_t>(from.model.ShStride());
  const GaussianModel& m = from.model;
  to.model.Add(m.positions[i], m.log_scales[i], m.rotations[i], m.opacity_logits[i],
               m.sh.data() + i * stride);
  const auto append = [&](const std::vector<float>& source, std::vector<float>& target, std::size_t width) {
    if (keep_optimizer_state)
      target.insert(target.end(), source.begin() + i * width, source.begin() + (i + 1) * width);
    else
      target.insert(target.end(), width, 0.0f);
  };
  append(from.m_geometry, to.m_geometry, kGeometryMomentFloats);
  append(from.v_geometry, to.v_geometry, kGeometryMomentFloats);
  append(from.m_sh, to.m_sh, stride);
  append(from.v_sh, to.v_sh, stride);
  // Statistics are reset after densification anyway.
  to.gradient_accum.push_back(0.0f);
  to.gradient_count.push_back(0);
  to.max_radius.push_back(0.0f);
}

float Sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

}  // namespace

DensifyResult DensifyAndPrune(OptimizerHostState& state, const TrainingOptions& options, double scene_extent,
                              std::uint64_t seed) {
  assert(state.Consistent());
  const std::size_t n = state.size();
  const GaussianModel& model = state.model;
  // Split children: scales / (0.8 N) with N = 2 children, as 3DGS.
  const float split_log_scale_delta = -std::log(1.6f);
  const double clone_limit = options.dense_fraction * scene_extent;
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);

  DensifyResult result;
  std::vector<NewGaussian> added;
  std::vector<char> split_parent(n, 0);
  std::size_t total = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (state.gradient_count[i] == 0) continue;
    const double mean_gradient = static_cast<double>(state.gradient_accum[i]) / state.gradient_count[i];
    if (!(mean_gradient >= options.densify_gradient_threshold)) continue;
    if (total + 1 > options.max_gaussians) break;
    ++total;  // a clone adds one; a split adds two children and removes the parent
    const Eigen::Vector3f scale = model.log_scales[i].array().exp();
    if (scale.maxCoeff() <= clone_limit) {
      added.push_back({i, model.positions[i], 0.0f});
      ++result.cloned;
      continue;
    }
    // Children ~ N(mu, R S S^T R^T): mu + R (s .* z), z ~ N(0, I).
    const Eigen::Matrix3f R = model.rotations[i].normalized().toRotationMatrix();
    for (int child = 0; child < 2; ++child) {
      const Eigen::Vector3f z(normal(rng), normal(rng), normal(rng));
      added.push_back({i, model.positions[i] + R * scale.cwiseProduct(z), split_log_scale_delta});
    }
    split_parent[i] = 1;
    ++result.split;
  }

  // Pruning: too transparent, or too large in the world.
  const auto prune = [&](float opacity_logit, const Eigen::Vector3f& log_scale) {
    return Sigmoid(opacity_logit) < options.prune_opacity ||
           std::exp(log_scale.maxCoeff()) > options.prune_world_fraction * scene_extent;
  };
  OptimizerHostState out;
  out.model.sh_degree = model.sh_degree;
  for (std::size_t i = 0; i < n; ++i) {
    if (split_parent[i]) continue;
    if (prune(model.opacity_logits[i], model.log_scales[i])) {
      ++result.pruned;
      continue;
    }
    Append(state, i, true, out);
  }
  for (const NewGaussian& g : added) {
    const Eigen::Vector3f log_scale = model.log_scales[g.parent].array() + g.log_scale_delta;
    if (prune(model.opacity_logits[g.parent], log_scale)) {
      ++result.pruned;
      continue;
    }
    Append(state, g.parent, false, out);
    out.model.positions.back() = g.position;
    out.model.log_scales.back() = log_scale;
  }
  state = std::move(out);
  state.ResetStatistics();
  assert(state.Consistent());
  return result;
}

void ResetOpacity(OptimizerHostState& state, float max_opacity) {
  assert(max_opacity > 0.0f && max_opacity < 1.0f);
  const float max_logit = std::log(max_opacity / (1.0f - max_opacity));
  for (std::size_t i = 0; i < state.size(); ++i) {
    state.model.opacity_logits[i] = std::min(state.model.opacity_logits[i], max_logit);
    state.m_geometry[i * kGeometryMomentFloats + kMomentOpacity] = 0.0f;
    state.v_geometry[i * kGeometryMomentFloats + kMomentOpacity] = 0.0f;
  }
}

}  // namespace uf::splat
