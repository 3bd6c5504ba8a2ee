// The Vulkan photometric loss pass (splat/vk/loss_pass.h, shaders/photometric_loss_*.comp) against its CPU
// reference EvaluatePhotometricLoss (itself checked against hand values and finite differences in
// test_photometric_loss.cpp): random rendered views are uploaded into colour / depth buffers laid out as the
// forward writes them, the pass runs alone in a frame, and the loss terms and the whole view-gradient buffer
// are compared. Also: determinism, a view without depth, image sizes below the window and the band height.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "splat/cpu_reference/photometric_loss.h"
#include "splat/vk/buffer.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/loss_pass.h"

namespace uf::splat::vk {
namespace {

struct Scene {
  RenderedView rendered;
  TrainingView target;
};

// Rendered rgb in [0, 1], alpha in (0, 1] with every 13th pixel below 1e-4 (no expected depth); the target a
// blend of the render and noise (SSIM ~ 0.5), LiDAR depth on ~70 % of the pixels near the expected depth.
Scene RandomScene(std::uint64_t seed, int width, int height) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  Scene s;
  s.rendered = RenderedView::Sized(width, height);
  for (float& v : s.rendered.rgb) v = uniform(rng);
  for (float v : s.rendered.rgb) s.target.rgb.push_back(0.6f * v + 0.4f * uniform(rng));
  for (int p = 0; p < width * height; ++p) {
    const float alpha = p % 13 == 5 ? 3e-5f : 0.02f + 0.98f * uniform(rng), E = 1.0f + 30.0f * uniform(rng);
    s.rendered.alpha[p] = alpha;
    s.rendered.depth[p] = E;
    s.rendered.expected_depth[p] = alpha < 1e-4f ? RenderedView::kNoDepth : E;
    s.target.depth.push_back(uniform(rng) < 0.3f ? 0.0f : E + 4.0f * (uniform(rng) - 0.5f));
  }
  s.target.camera.pinhole.width = width;
  s.target.camera.pinhole.height = height;
  return s;
}

class VulkanLoss : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto context = Context::Create({});
    ASSERT_TRUE(context.ok()) << context.error();
    context_ = std::move(context.value());
    auto frame = FrameCommands::Create(*context_, 16, 8);
    ASSERT_TRUE(frame.ok()) << frame.error();
    frame_ = std::move(frame.value());
    auto pass = LossPass::Create(*context_);
    ASSERT_TRUE(pass.ok()) << pass.error();
    pass_ = std::move(pass.value());
  }
  static void TearDownTestSuite() {
    // The buffers before the device they live on (static storage would otherwise outlive the context).
    colour_ = Buffer();
    depth_ = Buffer();
    gradients_ = Buffer();
    pass_.reset();
    frame_.reset();
    context_.reset();
  }

  // Runs the pass on `scene`; returns the view-gradient buffer (8 floats per pixel) and the loss.
  static std::vector<float> Run(const Scene& scene, const PhotometricLossWeights& weights,
                                PhotometricLossValue* loss) {
    const int width = scene.rendered.width, height = scene.rendered.height;
    const std::size_t pixels = static_cast<std::size_t>(width) * height;
    std::vector<float> colour(4 * pixels), depth(2 * pixels);
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int c = 0; c < 3; ++c) colour[4 * p + c] = scene.rendered.rgb[3 * p + c];
      colour[4 * p + 3] = scene.rendered.alpha[p];
      depth[2 * p] = scene.rendered.depth[p];
      depth[2 * p + 1] = scene.rendered.expected_depth[p];
    }
    EXPECT_TRUE(EnsureBuffer(*context_, colour_, colour.size() * 4, "colour").ok());
    EXPECT_TRUE(EnsureBuffer(*context_, depth_, depth.size() * 4, "depth").ok());
    EXPECT_TRUE(EnsureBuffer(*context_, gradients_, pixels * 32, "view gradients").ok());
    colour_.Upload(colour.data(), colour.size() * 4);
    depth_.Upload(depth.data(), depth.size() * 4);
    std::vector<float> garbage(pixels * 8, 1e30f);  // written whole: nothing of this may survive
    gradients_.Upload(garbage.data(), garbage.size() * 4);
    EXPECT_TRUE(pass_->Prepare(width, height).ok());
    pass_->UploadTarget(scene.target);
    EXPECT_TRUE(frame_->Begin().ok());
    pass_->Record(*frame_, colour_, depth_, gradients_, weights);
    const Status submitted = frame_->SubmitAndWait();
    EXPECT_TRUE(submitted.ok()) << submitted.message();
    *loss = pass_->ReadLoss();
    std::vector<float> out(pixels * 8);
    gradients_.Download(out.data(), out.size() * 4);
    return out;
  }

  static inline std::unique_ptr<Context> context_;
  static inline std::unique_ptr<FrameCommands> frame_;
  static inline std::unique_ptr<LossPass> pass_;
  static inline Buffer colour_, depth_, gradients_;
};

float MaxAbs(const std::vector<float>& v) {
  float m = 0;
  for (float x : v) m = std::max(m, std::abs(x));
  return m;
}

// Tolerances. The shaders compute in float what the reference computes in double. Loss terms: per-pixel S
// carries ~1e-7 relative error (the variances s = m - mu^2 cancel from moments ~0.3 to ~0.05), summed per
// band in float and over the bands in double; L1 and depth are float sums of |.|. Measured: <= 7e-8 (relative
// for l1 and depth, absolute for D-SSIM and total); the bound is 1e-6 (a missing border tap or a wrong
// constant moves D-SSIM by > 1e-4). Gradients: the L1 part is exact up to one rounding; the SSIM part
// A + 2 x B + y C sums float blurs of partials up to 1/C2 that partly cancel. Measured: <= 1e-6 of the
// largest rgb entry; the bound is 1e-5 (dropping one window tap changes entries by > 1e-3 of it). Depth
// gradients are one float product and division each, the same operations as the reference: 1e-6 relative.
void ExpectMatchesReference(const Scene& scene, const PhotometricLossWeights& weights,
                            const std::vector<float>& gpu, const PhotometricLossValue& loss) {
  const std::vector<float> no_depth;
  const PhotometricLoss reference = EvaluatePhotometricLoss(
      scene.rendered, scene.target.rgb, scene.target.depth.empty() ? no_depth : scene.target.depth, weights,
      scene.target.mask);
  EXPECT_NEAR(loss.l1, reference.l1, 1e-6 * reference.l1);
  EXPECT_NEAR(loss.dssim, reference.dssim, 1e-6);
  EXPECT_NEAR(loss.depth, reference.depth, 1e-6 * reference.depth + 1e-12);
  EXPECT_NEAR(loss.total, reference.total, 1e-6);
  const float rgb_scale = MaxAbs(reference.gradients.rgb), alpha_scale = MaxAbs(reference.gradients.alpha),
              depth_scale = MaxAbs(reference.gradients.depth_sum);
  float rgb_error = 0, alpha_error = 0, depth_error = 0, padding = 0;
  const std::size_t pixels = reference.gradients.alpha.size();
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c)
      rgb_error = std::max(rgb_error, std::abs(gpu[8 * p + c] - reference.gradients.rgb[3 * p + c]));
    alpha_error = std::max(alpha_error, std::abs(gpu[8 * p + 3] - reference.gradients.alpha[p]));
    depth_error = std::max(depth_error, std::abs(gpu[8 * p + 4] - reference.gradients.depth_sum[p]));
    padding =
        std::max({padding, std::abs(gpu[8 * p + 5]), std::abs(gpu[8 * p + 6]), std::abs(gpu[8 * p + 7])});
  }
  EXPECT_GT(rgb_scale, 0.0f);
  EXPECT_LT(rgb_error, 1e-5f * rgb_scale);
  EXPECT_LE(alpha_error, 1e-6f * alpha_scale);
  EXPECT_LE(depth_error, 1e-6f * depth_scale);
  EXPECT_EQ(padding, 0.0f);
}

TEST_F(VulkanLoss, MatchesTheCpuReference) {
  struct Case {
    std::uint64_t seed;
    int width, height;
    PhotometricLossWeights weights;
  };
  // Sizes: below the window in both directions, not a multiple of 64 columns / 16-row bands, the training
  // size.
  for (const Case& c :
       {Case{1, 13, 9, {0.2f, 0.5f}}, Case{2, 70, 45, {0.2f, 0.1f}}, Case{3, 64, 8, {1.0f, 0.0f}},
        Case{4, 5, 3, {0.0f, 1.0f}}, Case{5, 320, 240, {0.2f, 0.05f}}}) {
    SCOPED_TRACE("seed " + std::to_string(c.seed));
    const Scene scene = RandomScene(c.seed, c.width, c.height);
    PhotometricLossValue loss;
    const std::vector<float> gpu = Run(scene, c.weights, &loss);
    ExpectMatchesReference(scene, c.weights, gpu, loss);
    EXPECT_GT(loss.depth, 0.02);  // not vacuous: depth pairs exist (|E - d| / d ~ 0.1 on average)
  }
}

TEST_F(VulkanLoss, ViewWithoutDepthHasNoDepthTermAndIsDeterministic) {
  Scene scene = RandomScene(9, 90, 30);
  scene.target.depth.clear();
  const PhotometricLossWeights weights{0.2f, 1.0f};
  PhotometricLossValue loss, again;
  const std::vector<float> gpu = Run(scene, weights, &loss);
  ExpectMatchesReference(scene, weights, gpu, loss);
  EXPECT_EQ(loss.depth, 0.0);
  for (std::size_t p = 0; p < gpu.size() / 8; ++p) {
    ASSERT_EQ(gpu[8 * p + 3], 0.0f);
    ASSERT_EQ(gpu[8 * p + 4], 0.0f);
  }
  // No atomics: the same sums in the same order, bit for bit.
  const std::vector<float> repeated = Run(scene, weights, &again);
  EXPECT_EQ(std::memcmp(gpu.data(), repeated.data(), gpu.size() * 4), 0);
  EXPECT_EQ(loss.total, again.total);
}

TEST_F(VulkanLoss, MaskedPixelsMatchTheCpuReference) {
  // A band of masked rows and columns (an undistorted view's unfilled border) plus scattered pixels.
  Scene scene = RandomScene(11, 70, 45);
  scene.target.mask.assign(70 * 45, 1);
  for (int y = 0; y < 45; ++y)
    for (int x = 0; x < 70; ++x)
      if (x < 6 || y > 40 || (x * 7 + y * 3) % 17 == 0) scene.target.mask[y * 70 + x] = 0;
  const PhotometricLossWeights weights{0.2f, 0.5f};
  PhotometricLossValue loss;
  const std::vector<float> gpu = Run(scene, weights, &loss);
  ExpectMatchesReference(scene, weights, gpu, loss);
  for (std::size_t p = 0; p < scene.target.mask.size(); ++p) {
    if (scene.target.mask[p] != 0) continue;
    for (int k = 0; k < 5; ++k) ASSERT_EQ(gpu[8 * p + k], 0.0f) << "pixel " << p;
  }
}

TEST_F(VulkanLoss, RejectsAnEmptyImage) {
  EXPECT_FALSE(pass_->Prepare(0, 10).ok());
  EXPECT_FALSE(pass_->Prepare(10, -1).ok());
}

}  // namespace
}  // namespace uf::splat::vk
