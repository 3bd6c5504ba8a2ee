// The Vulkan compute renderer (on lavapipe here) against the CPU reference renderer on random scenes: every
// shader stage (projection, key emission, prefix sum, radix sort, tile ranges, rasterization) is covered by
// comparing the final images per pixel, plus the frame statistics against counts from the reference's
// projection; an empty model, a Gaussian behind the camera, depth ties, chunked uploads, key-buffer growth
// and the device-selection error.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/splat_renderer.h"
#include "tests/unit/splat/splat_test_support.h"

namespace uf::splat {
namespace {

using testing::Camera;
using testing::RandomScene;

struct Comparison {
  int mismatched = 0;  // pixels outside the tolerance
  int ambiguous = 0;   // pixels whose reference changes when min_alpha or the cut-off move by 1e-4
  int mismatched_but_not_ambiguous = 0;
  float max_colour_error = 0;  // over the matching pixels
};

// Tolerances. Both renderers compute in float from the same float camera, in the same order of
// operations; they differ by rounding (FMA contraction in the shader compiler, llvmpipe's exp, order of the
// matrix products): ~1e-6 relative per Gaussian, accumulated over at most a few hundred Gaussians per pixel
// with weights summing to <= 1, so colour and alpha agree within 1e-4 (absolute; values are O(1)) and the
// median depth (a t_z value) within 1e-5 relative. The expected depth D / alpha amplifies the alpha error
// 1e-6 by 1 / alpha: tolerance (1e-4 + 1e-5 / alpha) relative. Where a Gaussian's alpha sits at min_alpha,
// or T at the cut-off, within rounding, the two renderers may legitimately take different branches; such
// pixels are found by rendering the reference again with min_alpha and the cut-off moved by +-1e-4
// relative (far above rounding, far below any real change) and counted, not tolerated by looser bounds.
bool PixelMatches(const RenderedView& a, const RenderedView& b, std::size_t p, float* colour_error) {
  float error = 0;
  for (int c = 0; c < 3; ++c) error = std::max(error, std::abs(a.rgb[3 * p + c] - b.rgb[3 * p + c]));
  error = std::max(error, std::abs(a.alpha[p] - b.alpha[p]));
  if (colour_error) *colour_error = error;
  if (!(error <= 1e-4f)) return false;
  auto same_depth = [](float x, float y, float relative) {
    if (std::isinf(x) || std::isinf(y)) return x == y;
    return std::abs(x - y) <= relative * std::abs(y);
  };
  if (!same_depth(a.depth[p], b.depth[p], 1e-5f)) return false;
  return same_depth(a.expected_depth[p], b.expected_depth[p], 1e-4f + 1e-5f / std::max(b.alpha[p], 1e-4f));
}

Comparison Compare(const RenderedView& gpu, const GaussianModel& model, const SplatCamera& camera,
                   const RenderSettings& settings) {
  const RenderedView reference = RenderReference(model, camera, settings);
  std::vector<RenderedView> perturbed;
  for (const float f : {1 - 1e-4f, 1 + 1e-4f}) {
    RenderSettings s = settings;
    s.min_alpha *= f;
    s.transmittance_cutoff *= f;
    perturbed.push_back(RenderReference(model, camera, s));
  }
  Comparison result;
  for (std::size_t p = 0; p < reference.alpha.size(); ++p) {
    bool ambiguous = false;
    for (const RenderedView& other : perturbed) ambiguous |= !PixelMatches(other, reference, p, nullptr);
    float error = 0;
    const bool matches = PixelMatches(gpu, reference, p, &error);
    result.ambiguous += ambiguous;
    result.mismatched += !matches;
    result.mismatched_but_not_ambiguous += !matches && !ambiguous;
    if (matches) result.max_colour_error = std::max(result.max_colour_error, error);
  }
  return result;
}

class VulkanRenderer : public testing::SharedRendererTest {};

TEST_F(VulkanRenderer, MatchesTheReferenceOnRandomScenes) {
  ASSERT_NE(renderer_, nullptr);
  const SE3 T_world_camera(SO3::Exp(Eigen::Vector3d(0.2, -0.4, 0.3)), Eigen::Vector3d(3, -1, 2));
  struct Case {
    std::uint64_t seed;
    int gaussians, sh_degree, width, height;
  };
  for (const Case& c : {Case{1, 300, 0, 96, 64}, Case{2, 300, 1, 96, 64}, Case{3, 400, 2, 96, 64},
                        Case{4, 300, 3, 96, 64}, Case{5, 250, 3, 77, 45}, Case{6, 600, 1, 40, 130}}) {
    SCOPED_TRACE("seed " + std::to_string(c.seed));
    const SplatCamera camera = Camera(c.width, c.height, T_world_camera);
    const GaussianModel model = RandomScene(c.seed, c.gaussians, c.sh_degree, camera);
    RenderSettings settings;
    settings.background = {0.1f, 0.3f, 0.2f};
    ASSERT_TRUE(renderer_->Upload(model).ok());
    Expected<RenderedView> view = renderer_->Render(camera, settings);
    ASSERT_TRUE(view.ok()) << view.error();
    ASSERT_EQ(view->width, c.width);
    ASSERT_EQ(view->rgb.size(), 3u * c.width * c.height);
    const Comparison comparison = Compare(*view, model, camera, settings);
    EXPECT_EQ(comparison.mismatched_but_not_ambiguous, 0);
    EXPECT_LE(comparison.ambiguous, c.width * c.height / 200);  // the perturbation check stays rare
    EXPECT_LT(comparison.max_colour_error, 1e-4f);

    // Statistics against the reference's projection: visible Gaussians and tile-Gaussian pairs exactly.
    const FloatCamera float_camera = MakeFloatCamera(camera);
    std::size_t visible = 0, pairs = 0;
    for (std::size_t i = 0; i < model.size(); ++i) {
      const ProjectedGaussian g = ProjectGaussian(model, i, float_camera, settings);
      if (g.culled) continue;
      ++visible;
      pairs += static_cast<std::size_t>((g.tile_max - g.tile_min).prod());
    }
    const SplatFrameStats& stats = renderer_->last_frame_stats();
    EXPECT_EQ(stats.gaussians, model.size());
    EXPECT_EQ(stats.visible_gaussians, visible);
    EXPECT_EQ(stats.tile_gaussian_pairs, pairs);
    EXPECT_GT(stats.pixel_gaussian_pairs, 0u);
    EXPECT_LE(stats.pixel_gaussian_pairs, pairs * 256u);  // at most every pixel of every tile of every pair
  }
}

TEST_F(VulkanRenderer, DepthTiesBlendInIndexOrder) {
  // Gaussians at exactly the same depth (identity camera: t_z = mu_z exactly) with different colours.
  GaussianModel model;
  for (int i = 0; i < 6; ++i)
    model.AddConstantColor({0.05f * i, 0.02f * i, 3.0f}, Eigen::Vector3f::Constant(std::log(0.1f)),
                           Eigen::Quaternionf::Identity(), 1.0f, {i % 2 ? 1.0f : 0.0f, 0.2f * i, 0.5f});
  const SplatCamera camera = Camera(64, 48, SE3());
  ASSERT_TRUE(renderer_->Upload(model).ok());
  Expected<RenderedView> view = renderer_->Render(camera, {});
  ASSERT_TRUE(view.ok()) << view.error();
  const Comparison comparison = Compare(*view, model, camera, {});
  EXPECT_EQ(comparison.mismatched, 0);
}

TEST_F(VulkanRenderer, EmptyModelAndGaussianBehindGiveTheBackground) {
  RenderSettings settings;
  settings.background = {0.25f, 0.5f, 0.75f};
  const SplatCamera camera = Camera(50, 30, SE3());
  GaussianModel behind;
  behind.AddConstantColor({0, 0, -2}, Eigen::Vector3f::Constant(std::log(0.5f)),
                          Eigen::Quaternionf::Identity(), 5.0f, {1, 1, 1});
  for (const GaussianModel& model : {GaussianModel(), behind}) {
    ASSERT_TRUE(renderer_->Upload(model).ok());
    Expected<RenderedView> view = renderer_->Render(camera, settings);
    ASSERT_TRUE(view.ok()) << view.error();
    for (std::size_t p = 0; p < view->alpha.size(); ++p) {
      ASSERT_EQ(view->alpha[p], 0.0f);
      ASSERT_EQ(view->rgb[3 * p + 1], 0.5f);
      ASSERT_EQ(view->depth[p], RenderedView::kNoDepth);
      ASSERT_EQ(view->expected_depth[p], RenderedView::kNoDepth);
    }
    EXPECT_EQ(renderer_->last_frame_stats().visible_gaussians, 0u);
    EXPECT_EQ(renderer_->last_frame_stats().tile_gaussian_pairs, 0u);
  }
}

TEST_F(VulkanRenderer, RejectsBadInput) {
  GaussianModel bad = RandomScene(9, 10, 0, Camera(32, 32, SE3()));
  bad.log_scales[3].x() = NAN;
  const Status upload = renderer_->Upload(bad);
  ASSERT_FALSE(upload.ok());
  EXPECT_NE(upload.message().find("Gaussian 3"), std::string::npos) << upload.message();
  SplatCamera camera = Camera(32, 32, SE3());
  camera.pinhole.fx = -1;
  EXPECT_FALSE(renderer_->Render(camera, {}).ok());
  RenderSettings settings;
  settings.near = 0;
  Expected<RenderedView> view = renderer_->Render(Camera(32, 32, SE3()), settings);
  ASSERT_FALSE(view.ok());
  EXPECT_NE(view.error().find("near"), std::string::npos) << view.error();
}

TEST(VulkanRendererSetup, ChunkedUploadAndKeyBufferGrowthMatchTheReference) {
  // Chunks of 64 Gaussians (several device buffers, as 1 M Gaussians need), and large Gaussians whose
  // tile-Gaussian pairs exceed the initial key capacity of 4096: the first frame grows the buffers and
  // renders again (two submissions).
  SplatRendererOptions options;
  options.max_gaussians_per_chunk = 64;
  Expected<std::unique_ptr<SplatRenderer>> renderer = SplatRenderer::Create(options);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const SplatCamera camera =
      Camera(200, 150, SE3(SO3::Exp(Eigen::Vector3d(0.1, 0.2, 0)), Eigen::Vector3d::Zero()));
  GaussianModel model = RandomScene(11, 300, 2, camera);
  for (auto& log_scale : model.log_scales) log_scale.array() += 1.0f;  // 2.7x larger: ~30 tiles each
  ASSERT_TRUE((*renderer)->Upload(model).ok());
  Expected<RenderedView> view = (*renderer)->Render(camera, {});
  ASSERT_TRUE(view.ok()) << view.error();
  EXPECT_GT((*renderer)->last_frame_stats().tile_gaussian_pairs, 4096u);
  EXPECT_EQ((*renderer)->last_frame_stats().submissions, 2);
  const Comparison comparison = Compare(*view, model, camera, {});
  EXPECT_EQ(comparison.mismatched_but_not_ambiguous, 0);
  EXPECT_LE(comparison.ambiguous, 200 * 150 / 200);
  // The next frame fits.
  ASSERT_TRUE((*renderer)->Render(camera, {}).ok());
  EXPECT_EQ((*renderer)->last_frame_stats().submissions, 1);
}

TEST(VulkanRendererSetup, UnknownDeviceListsTheDevicesPresent) {
  for (const std::string name : {"no-such-gpu", "99"}) {
    SplatRendererOptions options;
    options.device = name;
    Expected<std::unique_ptr<SplatRenderer>> renderer = SplatRenderer::Create(options);
    ASSERT_FALSE(renderer.ok());
    EXPECT_NE(renderer.error().find("'" + name + "'"), std::string::npos) << renderer.error();
    EXPECT_NE(renderer.error().find("devices present: 0: "), std::string::npos) << renderer.error();
  }
  Expected<std::vector<std::string>> devices = ListSplatDevices();
  ASSERT_TRUE(devices.ok()) << devices.error();
  ASSERT_FALSE(devices->empty());
  // Choosing the first device by index and by a piece of its name works.
  SplatRendererOptions options;
  options.device = "0";
  Expected<std::unique_ptr<SplatRenderer>> by_index = SplatRenderer::Create(options);
  ASSERT_TRUE(by_index.ok()) << by_index.error();
  options.device = (*by_index)->device_name().substr(0, 4);
  Expected<std::unique_ptr<SplatRenderer>> by_name = SplatRenderer::Create(options);
  ASSERT_TRUE(by_name.ok()) << by_name.error();
  EXPECT_EQ((*by_name)->device_name(), (*by_index)->device_name());
  // FindSplatDevice makes the same choice without creating anything, and the same error.
  Expected<std::string> found = FindSplatDevice(options.device);
  ASSERT_TRUE(found.ok()) << found.error();
  EXPECT_EQ(*found, (*by_index)->device_name());
  Expected<std::string> missing = FindSplatDevice("no-such-gpu");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("no device matches 'no-such-gpu'; devices present: 0: "), std::string::npos)
      << missing.error();
}

}  // namespace
}  // namespace uf::splat
