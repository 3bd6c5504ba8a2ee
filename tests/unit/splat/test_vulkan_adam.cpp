// The Adam pass on Vulkan compute (splat/vk/adam_pass.h, shaders/adam_step.comp) against its CPU reference
// (AdamStepReference, whose update is the textbook rule written out once more here on one value): several
// steps on a random model split into chunks, random gradients, visibility and radii, with the active SH
// bands rising; the host round trip (Download / Upload, with a change of size); the device time at 100k.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "splat/training/adam_reference.h"
#include "splat/vk/adam_pass.h"
#include "splat/vk/frame_commands.h"
#include "tests/unit/splat/splat_test_support.h"

namespace uf::splat {
namespace {

using testing::Camera;
using testing::RandomScene;

class VulkanAdam : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto context = vk::Context::Create({});
    ASSERT_TRUE(context.ok()) << context.error();
    context_ = std::move(context.value());
    auto frame = vk::FrameCommands::Create(*context_, 512, 8);
    ASSERT_TRUE(frame.ok()) << frame.error();
    frame_ = std::move(frame.value());
  }
  static void TearDownTestSuite() {
    frame_.reset();
    context_.reset();
  }
  static inline std::unique_ptr<vk::Context> context_;
  static inline std::unique_ptr<vk::FrameCommands> frame_;
};

// Random gradients (normal; about one Gaussian in five unseen, with zero gradients), visibility and radii.
struct RandomInputs {
  GaussianGradients gradients;
  std::vector<std::uint32_t> seen;
  std::vector<float> radius;
};
RandomInputs MakeInputs(const GaussianModel& model, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::uniform_int_distribution<int> tiles(0, 4);
  RandomInputs in;
  in.gradients = GaussianGradients::Zero(model);
  const std::size_t stride = model.ShStride();
  for (std::size_t i = 0; i < model.size(); ++i) {
    in.seen.push_back(tiles(rng) > 0 ? static_cast<std::uint32_t>(tiles(rng) + 1) : 0);
    in.radius.push_back(std::floor(30.0f * std::abs(normal(rng))));
    if (in.seen[i] == 0) continue;
    in.gradients.position[i] = Eigen::Vector3f(normal(rng), normal(rng), normal(rng));
    in.gradients.log_scale[i] = Eigen::Vector3f(normal(rng), normal(rng), normal(rng));
    in.gradients.rotation[i] = Eigen::Vector4f(normal(rng), normal(rng), normal(rng), normal(rng));
    in.gradients.opacity_logit[i] = normal(rng);
    for (std::size_t k = 0; k < stride; ++k) in.gradients.sh[i * stride + k] = 0.1f * normal(rng);
    in.gradients.mean_2d[i] = Eigen::Vector2f(normal(rng), normal(rng)) * 1e-3f;
  }
  return in;
}

// Writes the inputs into device buffers laid out like the backward pass' output (backward_pass.h).
void WriteInputs(const vk::Context& context, const vk::GaussianBuffers& model, const RandomInputs& in,
                 std::vector<vk::GradientChunk>& chunks, vk::Buffer& tile_counts, vk::Buffer& projected) {
  const std::size_t stride = 3 * ShCoefficientsPerChannel(model.sh_degree), n = model.count;
  chunks.resize(model.chunks.size());
  ASSERT_TRUE(vk::EnsureBuffer(context, tile_counts, n * 4, "tile counts").ok());
  ASSERT_TRUE(vk::EnsureBuffer(context, projected, n * 48, "projected").ok());
  tile_counts.Upload(in.seen.data(), n * 4);
  auto* p = static_cast<float*>(projected.data());
  for (std::size_t i = 0; i < n; ++i) p[12 * i + 7] = in.radius[i];
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    const vk::GaussianChunk& chunk = model.chunks[c];
    ASSERT_TRUE(vk::EnsureBuffer(context, chunks[c].geometry, chunk.count * 64, "g").ok());
    ASSERT_TRUE(vk::EnsureBuffer(context, chunks[c].sh, chunk.count * stride * 4, "g sh").ok());
    auto* g = static_cast<float*>(chunks[c].geometry.data());
    for (std::uint32_t k = 0; k < chunk.count; ++k, g += 16) {
      const std::size_t i = chunk.first + k;
      for (int a = 0; a < 3; ++a) {
        g[a] = in.gradients.position[i][a];
        g[4 + a] = in.gradients.log_scale[i][a];
      }
      g[3] = in.gradients.opacity_logit[i];
      g[7] = 1e6f;  // unused slot: must not leak into anything
      for (int a = 0; a < 4; ++a) g[8 + a] = in.gradients.rotation[i][a];
      g[12] = in.gradients.mean_2d[i].x();
      g[13] = in.gradients.mean_2d[i].y();
    }
    chunks[c].sh.Upload(in.gradients.sh.data() + chunk.first * stride, chunk.count * stride * 4);
  }
}

// |gpu - reference| <= tolerance (|reference| + floor), element-wise, reporting the worst.
void ExpectClose(const std::vector<float>& gpu, const std::vector<float>& reference, float tolerance,
                 float floor, const char* what) {
  ASSERT_EQ(gpu.size(), reference.size()) << what;
  float worst = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const float error = std::abs(gpu[i] - reference[i]) / (std::abs(reference[i]) + floor);
    if (!(error <= worst)) worst = error, at = i;
  }
  EXPECT_LE(worst, tolerance) << what << " at " << at << ": " << gpu[at] << " vs " << reference[at];
}

std::vector<float> Flatten(const GaussianModel& m) {
  std::vector<float> out;
  for (std::size_t i = 0; i < m.size(); ++i) {
    out.insert(out.end(), m.positions[i].data(), m.positions[i].data() + 3);
    out.insert(out.end(), m.log_scales[i].data(), m.log_scales[i].data() + 3);
    out.insert(out.end(), {m.rotations[i].w(), m.rotations[i].x(), m.rotations[i].y(), m.rotations[i].z()});
    out.push_back(m.opacity_logits[i]);
  }
  out.insert(out.end(), m.sh.begin(), m.sh.end());
  return out;
}

AdamStep Step(int t, int active_sh_coefficients) {
  AdamStep step;  // distinct rates, so that a parameter updated at another group's rate shows
  step.lr_position = 0.011f;
  step.lr_log_scale = 0.013f;
  step.lr_rotation = 0.017f;
  step.lr_opacity = 0.019f;
  step.lr_sh_dc = 0.023f;
  step.lr_sh_rest = 0.029f;
  step.epsilon = 1e-8f;
  step.step = t;
  step.active_sh_coefficients = active_sh_coefficients;
  step.ndc_scale_x = 32.0f;
  step.ndc_scale_y = 24.0f;
  return step;
}

TEST(AdamReference, OneStepFromZeroMomentsMovesByTheLearningRate) {
  // From m = v = 0, step 1: m = (1 - b1) g, v = (1 - b2) g^2, m / c1 = g, v / c2 = g^2, so p -= lr sign(g)
  // (up to eps); the second step with the same g again moves by lr.
  GaussianModel model;
  model.AddConstantColor({1, 2, 3}, {0, 0, 0}, Eigen::Quaternionf::Identity(), 0.5f, {0.5f, 0.5f, 0.5f});
  OptimizerHostState state;
  state.model = model;
  state.ResizeToModel();
  GaussianGradients g = GaussianGradients::Zero(model);
  g.position[0] = {2.0f, -0.5f, 0.0f};
  g.mean_2d[0] = {3e-3f, -4e-3f};
  const AdamStep step = Step(1, 1);
  AdamStepReference(state, g, {1}, {5.0f}, step);
  EXPECT_NEAR(state.model.positions[0].x(), 1 - 0.011f, 1e-6f);
  EXPECT_NEAR(state.model.positions[0].y(), 2 + 0.011f, 1e-6f);
  EXPECT_EQ(state.model.positions[0].z(), 3.0f);
  EXPECT_NEAR(state.m_geometry[0], 0.1f * 2.0f, 1e-7f);
  EXPECT_NEAR(state.v_geometry[0], 0.001f * 4.0f, 1e-7f);  // 1 - 0.999f = 0.00099998713 in float
  // |(3e-3 * 32, -4e-3 * 24)| = |(0.096, -0.096)| = 0.13576.
  EXPECT_NEAR(state.gradient_accum[0], 0.096f * std::sqrt(2.0f), 1e-6f);
  EXPECT_EQ(state.gradient_count[0], 1u);
  EXPECT_EQ(state.max_radius[0], 5.0f);
  AdamStepReference(state, g, {0}, {9.0f}, Step(2, 1));
  EXPECT_NEAR(state.model.positions[0].x(), 1 - 2 * 0.011f, 1e-6f);
  EXPECT_EQ(state.gradient_count[0], 1u);  // unseen: statistics unchanged
  EXPECT_EQ(state.max_radius[0], 5.0f);
}

TEST_F(VulkanAdam, MatchesTheReferenceOverStepsAndChunks) {
  const SplatCamera camera = Camera(64, 48, SE3());
  const GaussianModel initial = RandomScene(5, 333, 3, camera);
  vk::GaussianBuffers buffers;
  ASSERT_TRUE(vk::UploadGaussians(*context_, initial, 70, buffers).ok());
  ASSERT_EQ(buffers.chunks.size(), 5u);
  auto pass = vk::AdamPass::Create(*context_, 70);
  ASSERT_TRUE(pass.ok()) << pass.error();
  ASSERT_TRUE((*pass)->Prepare(buffers).ok());
  OptimizerHostState reference;
  reference.model = initial;
  reference.ResizeToModel();
  std::vector<vk::GradientChunk> gradients;
  vk::Buffer tile_counts, projected;
  // Active SH bands: degree 0, 0, 1, 3 (1, 1, 4, 16 coefficients); the last step without radii.
  const int active[4] = {1, 1, 4, 16};
  for (int t = 1; t <= 4; ++t) {
    const RandomInputs in = MakeInputs(initial, 100 + t);
    WriteInputs(*context_, buffers, in, gradients, tile_counts, projected);
    const bool radii = t < 4;
    ASSERT_TRUE(frame_->Begin().ok());
    (*pass)->Record(*frame_, buffers, gradients, tile_counts, Step(t, active[t - 1]),
                    radii ? &projected : nullptr);
    ASSERT_TRUE(frame_->SubmitAndWait().ok());
    AdamStepReference(reference, in.gradients, in.seen, radii ? in.radius : std::vector<float>{},
                      Step(t, active[t - 1]));
  }
  ASSERT_TRUE((*pass)->Prepare(buffers).ok());  // unchanged model: keeps the state
  Expected<OptimizerHostState> gpu = (*pass)->Download(buffers);
  ASSERT_TRUE(gpu.ok()) << gpu.error();
  ASSERT_TRUE(gpu->Consistent());
  // Both sides do the same float operations (bit-identical on lavapipe); a GPU may fuse multiply-adds or
  // round sqrt / division differently: ~1e-7 of each term. A parameter moves by ~lr (0.01-0.03) per step, so
  // a rate of the wrong group (>= 10 % apart) or a missing bias correction is >= 1e-3 off.
  ExpectClose(Flatten(gpu->model), Flatten(reference.model), 1e-6f, 1.0f, "parameters");
  ExpectClose(gpu->m_geometry, reference.m_geometry, 1e-5f, 1e-6f, "m geometry");
  ExpectClose(gpu->v_geometry, reference.v_geometry, 1e-5f, 1e-6f, "v geometry");
  ExpectClose(gpu->m_sh, reference.m_sh, 1e-5f, 1e-6f, "m SH");
  ExpectClose(gpu->v_sh, reference.v_sh, 1e-5f, 1e-8f, "v SH");
  ExpectClose(gpu->gradient_accum, reference.gradient_accum, 1e-6f, 1e-6f, "gradient accumulators");
  EXPECT_EQ(gpu->gradient_count, reference.gradient_count);
  EXPECT_EQ(gpu->max_radius, reference.max_radius);
  // The higher bands did move once active (the inactive rule itself: InactiveShBands... below).
  const std::size_t stride = initial.ShStride();
  int changed_rest = 0;
  for (std::size_t i = 0; i < initial.size(); ++i)
    for (std::size_t k = 3; k < stride; ++k)
      changed_rest += gpu->model.sh[i * stride + k] != initial.sh[i * stride + k];
  EXPECT_GT(changed_rest, 0);
}

TEST_F(VulkanAdam, InactiveShBandsAndTheirMomentsStayAsTheyAre) {
  // Degree 2 (27 floats per Gaussian: the scalar path) and 3 (48: the vec4 path), degree 1 active.
  for (int degree : {2, 3}) {
    const GaussianModel initial = RandomScene(6, 150, degree, Camera(40, 30, SE3()));
    vk::GaussianBuffers buffers;
    ASSERT_TRUE(vk::UploadGaussians(*context_, initial, 64, buffers).ok());
    auto pass = vk::AdamPass::Create(*context_, 64);
    ASSERT_TRUE(pass.ok() && (*pass)->Prepare(buffers).ok());
    std::vector<vk::GradientChunk> gradients;
    vk::Buffer tile_counts, projected;
    WriteInputs(*context_, buffers, MakeInputs(initial, 9), gradients, tile_counts, projected);
    for (int t = 1; t <= 2; ++t) {
      ASSERT_TRUE(frame_->Begin().ok());
      (*pass)->Record(*frame_, buffers, gradients, tile_counts, Step(t, 4), &projected);
      ASSERT_TRUE(frame_->SubmitAndWait().ok());
    }
    Expected<OptimizerHostState> gpu = (*pass)->Download(buffers);
    ASSERT_TRUE(gpu.ok());
    const std::size_t stride = initial.ShStride();
    int moved = 0;
    for (std::size_t i = 0; i < initial.size(); ++i) {
      for (std::size_t k = 0; k < stride; ++k) {
        const std::size_t e = i * stride + k;
        if (k >= 12) {  // coefficients 4 and up: bit for bit unchanged, moments zero
          EXPECT_EQ(gpu->model.sh[e], initial.sh[e]) << degree;
          EXPECT_EQ(gpu->m_sh[e], 0.0f) << degree;
          EXPECT_EQ(gpu->v_sh[e], 0.0f) << degree;
        } else {
          moved += gpu->model.sh[e] != initial.sh[e];
        }
      }
    }
    EXPECT_GT(moved, static_cast<int>(initial.size()) * 12 / 2) << degree;
  }
}

TEST_F(VulkanAdam, HostRoundTripKeepsEverythingAndFollowsAChangeOfSize) {
  const GaussianModel initial = RandomScene(7, 200, 1, Camera(40, 30, SE3()));
  vk::GaussianBuffers buffers;
  ASSERT_TRUE(vk::UploadGaussians(*context_, initial, 64, buffers).ok());
  auto pass = vk::AdamPass::Create(*context_, 64);
  ASSERT_TRUE(pass.ok() && (*pass)->Prepare(buffers).ok());
  OptimizerHostState state;
  state.model = RandomScene(8, 333, 1, Camera(40, 30, SE3()));  // a different size: 6 chunks of <= 64
  state.ResizeToModel();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (std::vector<float>* v : {&state.m_geometry, &state.v_geometry, &state.m_sh, &state.v_sh,
                                &state.gradient_accum, &state.max_radius})
    for (float& x : *v) x = uniform(rng);
  for (std::uint32_t& c : state.gradient_count) c = static_cast<std::uint32_t>(100 * uniform(rng));
  ASSERT_TRUE((*pass)->Upload(state, *context_, buffers).ok());
  EXPECT_EQ(buffers.count, 333u);
  EXPECT_EQ(buffers.chunks.size(), 6u);
  Expected<OptimizerHostState> back = (*pass)->Download(buffers);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(Flatten(back->model), Flatten(state.model));
  EXPECT_EQ(back->m_geometry, state.m_geometry);
  EXPECT_EQ(back->v_geometry, state.v_geometry);
  EXPECT_EQ(back->m_sh, state.m_sh);
  EXPECT_EQ(back->v_sh, state.v_sh);
  EXPECT_EQ(back->gradient_accum, state.gradient_accum);
  EXPECT_EQ(back->gradient_count, state.gradient_count);
  EXPECT_EQ(back->max_radius, state.max_radius);
}

TEST_F(VulkanAdam, HundredThousandGaussiansOfDegreeThree) {
  const GaussianModel initial = RandomScene(9, 100000, 3, Camera(320, 240, SE3()));
  vk::GaussianBuffers buffers;
  ASSERT_TRUE(vk::UploadGaussians(*context_, initial, 0, buffers).ok());
  auto pass = vk::AdamPass::Create(*context_);
  ASSERT_TRUE(pass.ok() && (*pass)->Prepare(buffers).ok());
  std::vector<vk::GradientChunk> gradients;
  vk::Buffer tile_counts, projected;
  const RandomInputs in = MakeInputs(initial, 10);
  WriteInputs(*context_, buffers, in, gradients, tile_counts, projected);
  double best_ms = 1e9;
  OptimizerHostState reference;
  reference.model = initial;
  reference.ResizeToModel();
  for (int t = 1; t <= 3; ++t) {
    ASSERT_TRUE(frame_->Begin().ok());
    frame_->Timestamp();
    (*pass)->Record(*frame_, buffers, gradients, tile_counts, Step(t, 16), &projected);
    frame_->Timestamp();
    ASSERT_TRUE(frame_->SubmitAndWait().ok());
    const std::vector<double> ms = frame_->IntervalsMs();
    if (!ms.empty()) best_ms = std::min(best_ms, ms[0]);
    AdamStepReference(reference, in.gradients, in.seen, in.radius, Step(t, 16));
  }
  std::cout << "[ adam ] 100k Gaussians, SH degree 3: " << best_ms << " ms device time (best of 3)\n";
  Expected<OptimizerHostState> gpu = (*pass)->Download(buffers);
  ASSERT_TRUE(gpu.ok());
  ExpectClose(Flatten(gpu->model), Flatten(reference.model), 1e-6f, 1.0f, "parameters");
  EXPECT_EQ(gpu->gradient_count, reference.gradient_count);
}

}  // namespace
}  // namespace uf::splat
