// Adaptive density control (splat/training/densify.h) on hand-built optimizer states: clone / split / no-op
// just above and below each threshold, children drawn from the parent's Gaussian, pruning by opacity and
// world size, moments that move with their Gaussians, max_gaussians, the opacity reset, and the position
// learning-rate schedule (splat/training/learning_rate.h) against hand-computed values.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "splat/training/densify.h"
#include "splat/training/learning_rate.h"

namespace uf::splat {
namespace {

constexpr double kExtent = 10.0;  // clone limit 0.01 x 10 = 0.1 m, prune limit 0.1 x 10 = 1 m

TrainingOptions Options() {
  TrainingOptions options;  // threshold 2e-4, dense_fraction 0.01, prune_opacity 0.005, world fraction 0.1
  return options;
}

float Logit(float a) { return std::log(a / (1.0f - a)); }

// Appends a Gaussian of SH degree 1 whose every optimizer value encodes `tag` (moments tag + slot / 100),
// with statistics giving mean gradient `mean_gradient` over 4 views (0 views when mean_gradient < 0).
void AddGaussian(OptimizerHostState& state, float tag, float scale, float opacity, float mean_gradient,
                 const Eigen::Quaternionf& q = Eigen::Quaternionf::Identity()) {
  std::vector<float> sh(state.model.ShStride());
  for (std::size_t k = 0; k < sh.size(); ++k) sh[k] = tag + 0.01f * k;
  state.model.Add(Eigen::Vector3f(tag, 2 * tag, -tag), Eigen::Vector3f::Constant(std::log(scale)), q,
                  Logit(opacity), sh.data());
  for (std::size_t k = 0; k < kGeometryMomentFloats; ++k) {
    state.m_geometry.push_back(tag + 0.01f * k);
    state.v_geometry.push_back(tag + 0.02f * k);
  }
  for (std::size_t k = 0; k < sh.size(); ++k) {
    state.m_sh.push_back(tag + 0.03f * k);
    state.v_sh.push_back(tag + 0.04f * k);
  }
  state.gradient_count.push_back(mean_gradient < 0 ? 0 : 4);
  state.gradient_accum.push_back(mean_gradient < 0 ? 1.0f : 4 * mean_gradient);
  state.max_radius.push_back(7.0f);
}

OptimizerHostState EmptyState() {
  OptimizerHostState state;
  state.model.sh_degree = 1;
  return state;
}

// Index of the Gaussian whose position.x is tag (the first one), or -1.
int Find(const OptimizerHostState& state, float tag) {
  for (std::size_t i = 0; i < state.size(); ++i)
    if (state.model.positions[i].x() == tag) return static_cast<int>(i);
  return -1;
}

// The moments of Gaussian i equal those AddGaussian gave `tag` (kept) or are all zero (new).
void ExpectMoments(const OptimizerHostState& state, std::size_t i, float tag, bool kept) {
  const std::size_t stride = state.model.ShStride();
  for (std::size_t k = 0; k < kGeometryMomentFloats; ++k) {
    EXPECT_FLOAT_EQ(state.m_geometry[i * kGeometryMomentFloats + k], kept ? tag + 0.01f * k : 0.0f);
    EXPECT_FLOAT_EQ(state.v_geometry[i * kGeometryMomentFloats + k], kept ? tag + 0.02f * k : 0.0f);
  }
  for (std::size_t k = 0; k < stride; ++k) {
    EXPECT_FLOAT_EQ(state.m_sh[i * stride + k], kept ? tag + 0.03f * k : 0.0f);
    EXPECT_FLOAT_EQ(state.v_sh[i * stride + k], kept ? tag + 0.04f * k : 0.0f);
  }
}

TEST(Densify, ClonesSmallAndSplitsLargeGaussiansAboveTheGradientThreshold) {
  OptimizerHostState state = EmptyState();
  AddGaussian(state, 1, 0.099f, 0.5f, 2.01e-4f);  // clone: above threshold, scale below 0.1 m
  AddGaussian(state, 2, 0.099f, 0.5f, 1.99e-4f);  // below threshold: nothing
  AddGaussian(state, 3, 0.101f, 0.5f, 2.01e-4f,
              Eigen::Quaternionf(0.9f, 0.1f, -0.3f, 0.2f));  // split: scale above 0.1 m
  AddGaussian(state, 4, 0.5f, 0.5f, -1.0f);                  // never seen: nothing
  const DensifyResult result = DensifyAndPrune(state, Options(), kExtent, 7);
  EXPECT_EQ(result.cloned, 1u);
  EXPECT_EQ(result.split, 1u);
  EXPECT_EQ(result.pruned, 0u);
  ASSERT_TRUE(state.Consistent());
  ASSERT_EQ(state.size(), 6u);  // 1, 2, 4, clone of 1, 2 children of 3
  const std::vector<float> tags = {1, 2, 4, 1};
  for (std::size_t i = 0; i < tags.size(); ++i) {
    EXPECT_EQ(state.model.positions[i].x(), tags[i]) << i;
    EXPECT_NEAR(state.model.log_scales[i].x(), std::log(i == 2 ? 0.5f : 0.099f), 1e-6f);
    ExpectMoments(state, i, tags[i], i < 3);  // survivors keep their moments, the clone starts at zero
  }
  EXPECT_EQ(state.model.sh[3 * 12 + 5], 1.05f);  // the clone's SH
  for (std::size_t i = 4; i < 6; ++i) {  // split children: parent's rotation, opacity and SH, scale / 1.6
    EXPECT_NE(state.model.positions[i], Eigen::Vector3f(3, 6, -3));
    EXPECT_NEAR(state.model.log_scales[i].y(), std::log(0.101f / 1.6f), 1e-6f);
    EXPECT_EQ(state.model.rotations[i].coeffs(), Eigen::Quaternionf(0.9f, 0.1f, -0.3f, 0.2f).coeffs());
    EXPECT_NEAR(state.model.opacity_logits[i], 0.0f, 1e-6f);
    EXPECT_EQ(state.model.sh[i * 12 + 11], 3.11f);
    ExpectMoments(state, i, 3, false);
  }
  EXPECT_EQ(Find(state, 3), -1);                    // the parent is gone
  for (std::size_t i = 0; i < state.size(); ++i) {  // statistics reset
    EXPECT_EQ(state.gradient_count[i], 0u);
    EXPECT_EQ(state.gradient_accum[i], 0.0f);
    EXPECT_EQ(state.max_radius[i], 0.0f);
  }
}

TEST(Densify, PrunesTransparentAndHugeGaussiansAndMovesTheirMoments) {
  OptimizerHostState state = EmptyState();
  AddGaussian(state, 1, 0.5f, 0.0049f, 0);    // pruned: opacity below 0.005
  AddGaussian(state, 2, 0.5f, 0.0051f, 0);    // kept
  AddGaussian(state, 3, 1.01f, 0.5f, 0);      // pruned: larger than 1 m
  AddGaussian(state, 4, 0.99f, 0.5f, 0);      // kept
  AddGaussian(state, 5, 0.9f, 0.004f, 1.0f);  // split candidate, parent and children pruned (opacity)
  AddGaussian(state, 6, 0.05f, 0.9f, 1.0f);   // cloned, both kept
  const DensifyResult result = DensifyAndPrune(state, Options(), kExtent, 1);
  EXPECT_EQ(result.cloned, 1u);
  EXPECT_EQ(result.split, 1u);
  EXPECT_EQ(result.pruned, 4u);  // 1, 3 and both children of 5
  ASSERT_TRUE(state.Consistent());
  ASSERT_EQ(state.size(), 4u);
  const std::vector<float> tags = {2, 4, 6, 6};
  for (std::size_t i = 0; i < tags.size(); ++i) {
    EXPECT_EQ(state.model.positions[i].x(), tags[i]);
    ExpectMoments(state, i, tags[i], i < 3);
  }
}

TEST(Densify, SplitChildrenAreDrawnFromTheParentsGaussian) {
  const Eigen::Quaternionf q = Eigen::Quaternionf(0.7f, -0.2f, 0.5f, 0.3f).normalized();
  const Eigen::Vector3f sigma(0.4f, 0.1f, 0.2f), mu(1, 2, -1);
  OptimizerHostState state = EmptyState();
  const int parents = 2000;
  for (int i = 0; i < parents; ++i) {
    AddGaussian(state, 0, 1.0f, 0.5f, 1.0f, q);
    state.model.positions.back() = mu;
    state.model.log_scales.back() = sigma.array().log();
  }
  OptimizerHostState again = state;
  TrainingOptions options = Options();
  options.prune_world_fraction = 1.0;  // keep the 0.4 m Gaussians
  const DensifyResult result = DensifyAndPrune(state, options, kExtent, 42);
  ASSERT_EQ(result.split, static_cast<std::size_t>(parents));
  ASSERT_EQ(state.size(), 2u * parents);
  // In the parent's local frame, children / sigma ~ N(0, I): within 5 sigma, mean ~0 (standard error
  // 1 / sqrt(4000) = 0.016 per axis), variance ~1 (standard error sqrt(2 / 4000) = 0.022).
  const Eigen::Matrix3f R = q.toRotationMatrix();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_squares = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Eigen::Vector3f z = (R.transpose() * (state.model.positions[i] - mu)).cwiseQuotient(sigma);
    EXPECT_LT(z.cwiseAbs().maxCoeff(), 5.0f) << i;
    sum += z.cast<double>();
    sum_squares += z.cast<double>().cwiseAbs2();
  }
  const Eigen::Vector3d mean = sum / state.size(), variance = sum_squares / state.size() - mean.cwiseAbs2();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(mean[a], 0.0, 0.07) << a;
    EXPECT_NEAR(variance[a], 1.0, 0.1) << a;
  }
  // Deterministic per seed.
  OptimizerHostState same = again;
  DensifyAndPrune(same, options, kExtent, 42);
  EXPECT_EQ(same.model.positions, state.model.positions);
  DensifyAndPrune(again, options, kExtent, 43);
  EXPECT_NE(again.model.positions, state.model.positions);
}

TEST(Densify, StopsAddingAtMaxGaussians) {
  OptimizerHostState state = EmptyState();
  for (int i = 1; i <= 5; ++i) AddGaussian(state, i, 0.05f, 0.5f, 1.0f);  // all clone candidates
  TrainingOptions options = Options();
  options.max_gaussians = 7;
  DensifyResult result = DensifyAndPrune(state, options, kExtent, 1);
  EXPECT_EQ(result.cloned, 2u);
  ASSERT_EQ(state.size(), 7u);
  EXPECT_EQ(state.model.positions[5].x(), 1.0f);  // the first candidates by index
  EXPECT_EQ(state.model.positions[6].x(), 2.0f);
  // At the limit: a split (net +1) does not happen either.
  OptimizerHostState full = EmptyState();
  AddGaussian(full, 1, 0.5f, 0.5f, 1.0f);
  options.max_gaussians = 1;
  result = DensifyAndPrune(full, options, kExtent, 1);
  EXPECT_EQ(result.split + result.cloned, 0u);
  EXPECT_EQ(full.size(), 1u);
}

TEST(Densify, ResetOpacityClampsLogitsAndZerosTheirMoments) {
  OptimizerHostState state = EmptyState();
  const std::vector<float> opacities = {0.001f, 0.0099f, 0.5f, 0.99f};
  for (std::size_t i = 0; i < opacities.size(); ++i) AddGaussian(state, i + 1, 0.1f, opacities[i], 0);
  ResetOpacity(state);
  const float cap = std::log(0.01f / 0.99f);  // -4.59512
  EXPECT_NEAR(cap, -4.59512f, 1e-5f);
  const std::vector<float> expected = {Logit(0.001f), Logit(0.0099f), cap, cap};
  for (std::size_t i = 0; i < opacities.size(); ++i) {
    EXPECT_FLOAT_EQ(state.model.opacity_logits[i], expected[i]);
    for (std::size_t k = 0; k < kGeometryMomentFloats; ++k) {  // only the opacity moments are zeroed
      const float tag = i + 1.0f;
      EXPECT_FLOAT_EQ(state.m_geometry[i * kGeometryMomentFloats + k],
                      k == kMomentOpacity ? 0 : tag + 0.01f * k);
      EXPECT_FLOAT_EQ(state.v_geometry[i * kGeometryMomentFloats + k],
                      k == kMomentOpacity ? 0 : tag + 0.02f * k);
    }
  }
}

TEST(LearningRate, PositionRateDecaysLogLinearlyTimesTheExtent) {
  TrainingOptions options;  // 1.6e-4 -> 1.6e-6 over 3000 iterations
  const double extent = 2.0;
  EXPECT_NEAR(PositionLearningRate(options, 0, extent), 3.2e-4, 1e-12);
  // Half way: the geometric mean sqrt(1.6e-4 * 1.6e-6) = 1.6e-5; a quarter: 1.6e-4 * 0.01^0.25.
  EXPECT_NEAR(PositionLearningRate(options, 1500, extent), 3.2e-5, 1e-12);
  EXPECT_NEAR(PositionLearningRate(options, 750, extent), 2 * 1.6e-4 * 0.31622776601683794, 1e-12);
  EXPECT_NEAR(PositionLearningRate(options, 3000, extent), 3.2e-6, 1e-14);
  EXPECT_NEAR(PositionLearningRate(options, 5000, extent), 3.2e-6, 1e-14);  // clamped after the end
}

}  // namespace
}  // namespace uf::splat
