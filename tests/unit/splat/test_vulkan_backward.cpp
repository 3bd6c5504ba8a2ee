// The Vulkan backward pass (shaders/rasterize_backward.comp, project_backward.comp through
// SplatRenderer::Backward) against the CPU reference backward (RenderReferenceBackward, itself checked
// against finite differences in test_reference_backward.cpp) on random scenes of SH degree 0..3 with loss
// weights on rgb, alpha and the depth sum; chunked uploads, determinism, an empty model and bad input; the
// passes with an active SH degree below the model's (training) against the reference on the truncated model.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "splat/cpu_reference/reference_backward.h"
#include "splat/cpu_reference/reference_renderer.h"
#include "splat/splat_renderer.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/forward_pass.h"
#include "tests/unit/splat/splat_test_support.h"

namespace uf::splat {
namespace {

using testing::Camera;
using testing::RandomScene;

// dL/d(images) of a random loss: normal weights on rgb and alpha, and on the depth sum scaled to the scene
// depth (so that every term matters).
ViewGradients RandomViewGradients(std::uint64_t seed, int pixels) {
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  ViewGradients g;
  for (int p = 0; p < 3 * pixels; ++p) g.rgb.push_back(normal(rng));
  for (int p = 0; p < pixels; ++p) g.alpha.push_back(normal(rng));
  for (int p = 0; p < pixels; ++p) g.depth_sum.push_back(0.1f * normal(rng));
  return g;
}

// Largest |difference| between the two gradient groups relative to the largest |reference| entry of the
// group. Float rounding: both sides sum the same per-pixel terms in float but in a different order (the
// reference per Gaussian over pixels in raster order; the shaders per pixel group, subgroup and tile), and
// the shader recovers T_i by dividing by (1 - a_i) instead of keeping the forward's products: each term
// carries ~1e-7..1e-6 relative error, and sums of a few hundred terms of both signs leave up to ~1e-5 of the
// group's largest entry (measured: 0.5e-6..7.3e-6 over these scenes). 5e-5 leaves margin for another exp/log
// implementation; a wrong formula, sign or index gives >= 1e-2 (a 10 % change of one term of dL/dalpha:
// 0.016..0.14).
template <typename Vector>
float RelativeError(const std::vector<Vector>& gpu, const std::vector<Vector>& reference) {
  float scale = 0, error = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    scale = std::max(scale, Eigen::Ref<const Eigen::VectorXf>(reference[i]).cwiseAbs().maxCoeff());
    error = std::max(error, Eigen::Ref<const Eigen::VectorXf>(gpu[i] - reference[i]).cwiseAbs().maxCoeff());
  }
  return scale > 0 ? error / scale : error;
}
float RelativeError(const std::vector<float>& gpu, const std::vector<float>& reference) {
  float scale = 0, error = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    scale = std::max(scale, std::abs(reference[i]));
    error = std::max(error, std::abs(gpu[i] - reference[i]));
  }
  return scale > 0 ? error / scale : error;
}

constexpr float kTolerance = 5e-5f;  // see RelativeError

void ExpectGeometryGradientsMatch(const GaussianGradients& gpu, const GaussianGradients& reference) {
  EXPECT_LT(RelativeError(gpu.position, reference.position), kTolerance);
  EXPECT_LT(RelativeError(gpu.log_scale, reference.log_scale), kTolerance);
  EXPECT_LT(RelativeError(gpu.rotation, reference.rotation), kTolerance);
  EXPECT_LT(RelativeError(gpu.opacity_logit, reference.opacity_logit), kTolerance);
  EXPECT_LT(RelativeError(gpu.mean_2d, reference.mean_2d), kTolerance);
}

class VulkanBackward : public testing::SharedRendererTest {
 protected:
  static Expected<GaussianGradients> Run(SplatRenderer& renderer, const GaussianModel& model,
                                         const SplatCamera& camera, const RenderSettings& settings,
                                         const ViewGradients& gradients) {
    if (Status s = renderer.Upload(model); !s.ok()) return s;
    Expected<RenderedView> view = renderer.Render(camera, settings);
    if (!view.ok()) return view.status();
    return renderer.Backward(gradients);
  }
};

const SE3 kPose(SO3::Exp(Eigen::Vector3d(0.2, -0.4, 0.3)), Eigen::Vector3d(3, -1, 2));

TEST_F(VulkanBackward, MatchesTheReferenceBackwardOnRandomScenes) {
  ASSERT_NE(renderer_, nullptr);
  struct Case {
    std::uint64_t seed;
    int gaussians, sh_degree, width, height;
  };
  for (const Case& c : {Case{11, 200, 0, 64, 48}, Case{12, 250, 1, 70, 45}, Case{13, 300, 2, 64, 64},
                        Case{14, 200, 3, 50, 37}, Case{15, 300, 3, 80, 48}}) {
    SCOPED_TRACE("seed " + std::to_string(c.seed));
    const SplatCamera camera = Camera(c.width, c.height, kPose);
    const GaussianModel model = RandomScene(c.seed, c.gaussians, c.sh_degree, camera);
    RenderSettings settings;
    settings.background = {0.1f, 0.3f, 0.2f};
    const ViewGradients dL_dview = RandomViewGradients(c.seed, c.width * c.height);
    Expected<GaussianGradients> gpu = Run(*renderer_, model, camera, settings, dL_dview);
    ASSERT_TRUE(gpu.ok()) << gpu.error();
    const GaussianGradients reference = RenderReferenceBackward(model, camera, settings, dL_dview);
    ASSERT_EQ(gpu->position.size(), model.size());
    ASSERT_EQ(gpu->sh.size(), reference.sh.size());
    ExpectGeometryGradientsMatch(*gpu, reference);
    EXPECT_LT(RelativeError(gpu->sh, reference.sh), kTolerance);
    // Not vacuous: most visible Gaussians get gradients.
    int nonzero = 0;
    for (const Eigen::Vector3f& g : reference.position) nonzero += g.norm() > 0;
    EXPECT_GT(nonzero, c.gaussians / 3);
  }
}

// Opaque, overlapping Gaussians: most pixels stop at the transmittance cut-off and many alphas are clamped
// at max_alpha (no gradient through the clamp), which is where the backward's use of the forward's per-pixel
// end index and final transmittance must agree with the reference exactly.
TEST_F(VulkanBackward, MatchesTheReferenceWhereBlendingStopsEarlyAndAlphaIsClamped) {
  ASSERT_NE(renderer_, nullptr);
  const SplatCamera camera = Camera(64, 48, kPose);
  GaussianModel model = RandomScene(31, 400, 1, camera);
  for (std::size_t i = 0; i < model.size(); ++i) {
    model.opacity_logits[i] = i % 2 ? 6.0f : 2.0f;           // opacity 0.9975 (clamped at 0.99) or 0.88
    model.log_scales[i] += Eigen::Vector3f::Constant(0.7f);  // twice the size: heavy overlap
  }
  const RenderSettings settings;
  const RenderedView reference_view = RenderReference(model, camera, settings);
  int saturated = 0;
  for (const float alpha : reference_view.alpha) saturated += alpha > 1.0f - 2e-3f;
  ASSERT_GT(saturated, static_cast<int>(reference_view.alpha.size()) / 2) << "the cut-off must matter";
  const ViewGradients dL_dview = RandomViewGradients(31, 64 * 48);
  Expected<GaussianGradients> gpu = Run(*renderer_, model, camera, settings, dL_dview);
  ASSERT_TRUE(gpu.ok()) << gpu.error();
  const GaussianGradients reference = RenderReferenceBackward(model, camera, settings, dL_dview);
  ExpectGeometryGradientsMatch(*gpu, reference);
  EXPECT_LT(RelativeError(gpu->sh, reference.sh), kTolerance);
}

TEST_F(VulkanBackward, ChunkedUploadAndRepeatedRunsGiveIdenticalGradients) {
  const SplatCamera camera = Camera(64, 48, kPose);
  const GaussianModel model = RandomScene(21, 300, 2, camera);
  const ViewGradients dL_dview = RandomViewGradients(21, 64 * 48);
  SplatRendererOptions options;
  options.max_gaussians_per_chunk = 70;  // 5 chunks
  Expected<std::unique_ptr<SplatRenderer>> chunked = SplatRenderer::Create(options);
  ASSERT_TRUE(chunked.ok()) << chunked.error();
  Expected<GaussianGradients> a = Run(*renderer_, model, camera, {}, dL_dview);
  Expected<GaussianGradients> b = Run(**chunked, model, camera, {}, dL_dview);
  Expected<GaussianGradients> again = (*chunked)->Backward(dL_dview);
  ASSERT_TRUE(a.ok() && b.ok() && again.ok());
  // No atomics: the same sums in the same order, bit for bit.
  for (const GaussianGradients* other : {&b.value(), &again.value()}) {
    EXPECT_EQ(a->position, other->position);
    EXPECT_EQ(a->log_scale, other->log_scale);
    EXPECT_EQ(a->rotation, other->rotation);
    EXPECT_EQ(a->opacity_logit, other->opacity_logit);
    EXPECT_EQ(a->sh, other->sh);
    EXPECT_EQ(a->mean_2d, other->mean_2d);
  }
}

TEST_F(VulkanBackward, EmptyModelAndCulledGaussiansGetNoGradient) {
  const SplatCamera camera = Camera(40, 30, SE3());
  const ViewGradients dL_dview = RandomViewGradients(3, 40 * 30);
  Expected<GaussianGradients> empty = Run(*renderer_, GaussianModel(), camera, {}, dL_dview);
  ASSERT_TRUE(empty.ok()) << empty.error();
  EXPECT_TRUE(empty->position.empty() && empty->sh.empty() && empty->mean_2d.empty());

  GaussianModel behind;
  behind.AddConstantColor({0, 0, -2}, Eigen::Vector3f::Constant(std::log(0.5f)),
                          Eigen::Quaternionf::Identity(), 5.0f, {1, 1, 1});
  Expected<GaussianGradients> culled = Run(*renderer_, behind, camera, {}, dL_dview);
  ASSERT_TRUE(culled.ok()) << culled.error();
  ASSERT_EQ(culled->position.size(), 1u);
  EXPECT_EQ(culled->position[0], Eigen::Vector3f::Zero());
  EXPECT_EQ(culled->opacity_logit[0], 0.0f);
  EXPECT_EQ(culled->sh, std::vector<float>(3, 0.0f));
}

TEST_F(VulkanBackward, RejectsBackwardWithoutRenderAndWrongSizes) {
  const SplatCamera camera = Camera(40, 30, SE3());
  const GaussianModel model = RandomScene(4, 20, 0, camera);
  ASSERT_TRUE(renderer_->Upload(model).ok());
  const ViewGradients dL_dview = RandomViewGradients(4, 40 * 30);
  Expected<GaussianGradients> before = renderer_->Backward(dL_dview);
  ASSERT_FALSE(before.ok());
  EXPECT_NE(before.error().find("Render"), std::string::npos) << before.error();
  ASSERT_TRUE(renderer_->Render(camera, {}).ok());
  ViewGradients wrong = dL_dview;
  wrong.alpha.pop_back();
  Expected<GaussianGradients> sized = renderer_->Backward(wrong);
  ASSERT_FALSE(sized.ok());
  EXPECT_NE(sized.error().find("alpha has 1199 entries, expected 1200"), std::string::npos) << sized.error();
}

// The passes themselves, recorded into one frame as the trainer records them: a device, the frame's commands
// and a forward pass (the backward pass is the test's).
class VulkanPasses : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = vk::Context::Create({});
    ASSERT_TRUE(context.ok()) << context.error();
    context_ = std::move(*context);
    auto frame = vk::FrameCommands::Create(*context_, 64, 24);
    ASSERT_TRUE(frame.ok()) << frame.error();
    frame_ = std::move(*frame);
    auto forward = vk::ForwardPass::Create(*context_);
    ASSERT_TRUE(forward.ok()) << forward.error();
    forward_ = std::move(*forward);
  }
  std::unique_ptr<vk::Context> context_;
  std::unique_ptr<vk::FrameCommands> frame_;
  std::unique_ptr<vk::ForwardPass> forward_;
};

// The forward and backward passes with active SH degree a < 3 on a degree-3 model whose higher bands are
// nonzero: the image and the gradients must be those of the model truncated to degree a (WithShDegree; CPU
// reference), the SH gradients above a exactly zero. Degrees in the order 3, 0, 2, 1 on the same passes: the
// zero gradients above a must hold after a frame that wrote them.
TEST_F(VulkanPasses, ActiveShDegreeMatchesTheReferenceOfTheTruncatedModel) {
  vk::Context* context = context_.get();
  vk::FrameCommands* frame = frame_.get();
  vk::ForwardPass* forward = forward_.get();
  auto backward = vk::BackwardPass::Create(*context);
  ASSERT_TRUE(backward.ok()) << backward.error();
  const SplatCamera camera = Camera(64, 48, kPose);
  const GaussianModel model = RandomScene(21, 250, 3, camera);
  vk::GaussianBuffers gaussians;
  ASSERT_TRUE(vk::UploadGaussians(*context, model, 100, gaussians).ok());  // 3 chunks
  RenderSettings settings;
  settings.background = {0.2f, 0.1f, 0.3f};
  const ViewGradients dL_dview = RandomViewGradients(21, camera.pinhole.width * camera.pinhole.height);
  const std::size_t stride = model.ShStride();
  for (int active : {3, 0, 2, 1}) {
    SCOPED_TRACE("active SH degree " + std::to_string(active));
    bool done = false;
    for (int attempt = 0; attempt < 2 && !done; ++attempt) {
      ASSERT_TRUE(forward->Prepare(gaussians, MakeFloatCamera(camera), settings, active).ok());
      ASSERT_TRUE(frame->Begin().ok());
      forward->Record(*frame, gaussians);
      const vk::ForwardState state = forward->State(gaussians);
      ASSERT_TRUE((*backward)->Prepare(state).ok());
      (*backward)->UploadViewGradients(
          dL_dview, static_cast<std::size_t>(camera.pinhole.width) * camera.pinhole.height);
      (*backward)->Record(*frame, state);
      ASSERT_TRUE(frame->SubmitAndWait().ok());
      SplatFrameStats stats;
      done = forward->Finish(&stats);
    }
    ASSERT_TRUE(done);
    RenderedView view;
    forward->ReadView(&view);
    GaussianGradients gpu;
    (*backward)->Download(forward->State(gaussians), &gpu);

    const GaussianModel truncated = WithShDegree(model, active);
    const RenderedView expected_view = RenderReference(truncated, camera, settings);
    float rgb_error = 0;
    for (std::size_t i = 0; i < view.rgb.size(); ++i)
      rgb_error = std::max(rgb_error, std::abs(view.rgb[i] - expected_view.rgb[i]));
    EXPECT_LT(rgb_error, 1e-4f);  // as test_vulkan_renderer's image tolerance

    const GaussianGradients reference = RenderReferenceBackward(truncated, camera, settings, dL_dview);
    ExpectGeometryGradientsMatch(gpu, reference);
    // SH: the active coefficients as the truncated model's, the others exactly zero.
    const std::size_t active_floats = truncated.ShStride();
    ASSERT_EQ(gpu.sh.size(), model.size() * stride);
    std::vector<float> gpu_active;
    int nonzero_above = 0;
    for (std::size_t i = 0; i < model.size(); ++i)
      for (std::size_t k = 0; k < stride; ++k) {
        const float g = gpu.sh[i * stride + k];
        if (k < active_floats)
          gpu_active.push_back(g);
        else
          nonzero_above += g != 0.0f;
      }
    EXPECT_LT(RelativeError(gpu_active, reference.sh), kTolerance);
    EXPECT_EQ(nonzero_above, 0);
    // Not vacuous: the higher bands change the image (the first case renders all of them).
    if (active == 0) {
      const RenderedView full = RenderReference(model, camera, settings);
      float difference = 0;
      for (std::size_t i = 0; i < full.rgb.size(); ++i)
        difference = std::max(difference, std::abs(full.rgb[i] - expected_view.rgb[i]));
      EXPECT_GT(difference, 1e-2f);
    }
  }
}

// The pair records split over the backward's three pages (backward_pass.h): with pages a third of the
// frame's pair capacity long, so that every page holds records and Gaussians have records in two, the
// gradients are bit for bit those of one page, and the reference's; more pairs than the pages hold is a
// clear error, not a write past the buffer.
TEST_F(VulkanPasses, PairRecordsAcrossThreePagesGiveTheSameGradients) {
  vk::Context* context = context_.get();
  vk::FrameCommands* frame = frame_.get();
  vk::ForwardPass* forward = forward_.get();
  const SplatCamera camera = Camera(64, 48, kPose);
  // Enough Gaussians that the pairs outgrow the first guess of the key capacity, which then becomes 1.25x
  // the pairs: pages of a third of it leave records on all three.
  const GaussianModel model = RandomScene(31, 1500, 1, camera);
  vk::GaussianBuffers gaussians;
  ASSERT_TRUE(vk::UploadGaussians(*context, model, 512, gaussians).ok());
  RenderSettings settings;
  const ViewGradients dL_dview = RandomViewGradients(31, camera.pinhole.width * camera.pinhole.height);
  struct Pairs {
    std::size_t capacity = 0, used = 0;  // slots the frame was prepared for (0: Prepare refused), pairs
  };
  // One frame through `backward`, and its gradients.
  auto run = [&](vk::BackwardPass& backward, GaussianGradients* gradients, std::string* error) {
    Pairs pairs;
    for (int attempt = 0; attempt < 2; ++attempt) {
      EXPECT_TRUE(forward->Prepare(gaussians, MakeFloatCamera(camera), settings, 1).ok());
      EXPECT_TRUE(frame->Begin().ok());
      forward->Record(*frame, gaussians);
      const vk::ForwardState state = forward->State(gaussians);
      if (Status s = backward.Prepare(state); !s.ok()) {
        *error = s.message();
        return Pairs{};
      }
      backward.UploadViewGradients(dL_dview,
                                   static_cast<std::size_t>(camera.pinhole.width) * camera.pinhole.height);
      backward.Record(*frame, state);
      EXPECT_TRUE(frame->SubmitAndWait().ok());
      SplatFrameStats stats;
      pairs = {state.pairs, 0};
      const bool done = forward->Finish(&stats);
      pairs.used = stats.tile_gaussian_pairs;
      if (done) break;
    }
    backward.Download(forward->State(gaussians), gradients);
    return pairs;
  };
  auto one_page = vk::BackwardPass::Create(*context);
  ASSERT_TRUE(one_page.ok()) << one_page.error();
  GaussianGradients single;
  std::string error;
  const Pairs pairs = run(**one_page, &single, &error);
  const std::size_t page = (pairs.capacity + 2) / 3;
  ASSERT_GT(pairs.used, 2 * page) << "capacity " << pairs.capacity << error;

  auto paged_pass = vk::BackwardPass::Create(*context, page);
  ASSERT_TRUE(paged_pass.ok()) << paged_pass.error();
  GaussianGradients paged;
  ASSERT_EQ(run(**paged_pass, &paged, &error).used, pairs.used) << error;
  EXPECT_EQ(paged.position, single.position);
  EXPECT_EQ(paged.log_scale, single.log_scale);
  EXPECT_EQ(paged.rotation, single.rotation);
  EXPECT_EQ(paged.opacity_logit, single.opacity_logit);
  EXPECT_EQ(paged.sh, single.sh);
  EXPECT_EQ(paged.mean_2d, single.mean_2d);
  ExpectGeometryGradientsMatch(paged, RenderReferenceBackward(model, camera, settings, dL_dview));

  auto too_small = vk::BackwardPass::Create(*context, pairs.capacity / 3 - 1);
  ASSERT_TRUE(too_small.ok()) << too_small.error();
  GaussianGradients refused;
  EXPECT_EQ(run(**too_small, &refused, &error).capacity, 0u);
  EXPECT_NE(error.find("tile-Gaussian pairs in one view exceed the backward's"), std::string::npos) << error;
}

}  // namespace
}  // namespace uf::splat
