// CameraViewRenderer with the CPU reference renderer: a camera without distortion renders exactly the
// reference view of its own pinhole; with distortion, a small splat lands where the camera model projects its
// centre (and not where the undistorted pinhole would, 2.5 px away); the renderer's errors pass through.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/views/camera_view_renderer.h"

namespace uf::splat {
namespace {

const SE3 kPose(SO3::Exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(1, 2, 3));

// One small bright splat (sigma 2 cm, about half a pixel at 2 m) at the camera-frame point p_camera.
GaussianModel Splat(const Eigen::Vector3d& p_camera) {
  GaussianModel model;
  model.sh_degree = 0;
  model.AddConstantColor((kPose * p_camera).cast<float>(), Eigen::Vector3f::Constant(std::log(0.02f)),
                         Eigen::Quaternionf::Identity(), 3.0f, Eigen::Vector3f::Ones());
  return model;
}

// Renders with the CPU reference and remembers the pinhole camera it was asked for.
struct ReferenceRender {
  const GaussianModel* model = nullptr;
  SplatCamera* asked = nullptr;
  Expected<RenderedView> operator()(const SplatCamera& camera, const RenderSettings& settings) const {
    *asked = camera;
    return RenderReference(*model, camera, settings);
  }
};

TEST(CameraViewRenderer, WithoutDistortionItIsTheReferenceViewOfTheModelsPinhole) {
  const PinholeRadtan model(PinholeRadtanIntrinsics{{48, 32, 40, 41, 23.5, 15.25}});
  Expected<CameraViewRenderer> renderer = CameraViewRenderer::Create(model);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  EXPECT_FALSE(renderer->distorted());
  const GaussianModel scene = Splat(Eigen::Vector3d(0.3, -0.2, 2));
  RenderSettings settings;
  settings.background = {0.1f, 0.2f, 0.3f};
  SplatCamera asked;
  Expected<RenderedView> view = renderer->Render(kPose, settings, ReferenceRender{&scene, &asked});
  ASSERT_TRUE(view.ok()) << view.error();
  EXPECT_EQ(asked.pinhole, (PinholeIntrinsics{48, 32, 40, 41, 23.5, 15.25}));
  EXPECT_EQ(asked.T_world_camera.matrix(), kPose.matrix());
  const RenderedView reference = RenderReference(scene, asked, settings);
  EXPECT_EQ(view->rgb, reference.rgb);
  EXPECT_EQ(view->alpha, reference.alpha);
  EXPECT_EQ(view->depth, reference.depth);
}

TEST(CameraViewRenderer, WithDistortionASplatLandsWhereTheModelProjectsIt) {
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 64, .height = 48, .fx = 50, .fy = 50, .cx = 31.5, .cy = 23.5};
  k.k1 = -0.3, k.k2 = 0.08;
  const PinholeRadtan model(k);
  Expected<CameraViewRenderer> renderer = CameraViewRenderer::Create(model);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  EXPECT_TRUE(renderer->distorted());
  // x/z = 0.5, y/z = 0.35: r^2 = 0.3725, the radial factor 1 - 0.3 r^2 + 0.08 r^4 = 0.899 pulls the splat
  // from the pinhole's (56.5, 41.0) to (53.98, 39.24).
  const Eigen::Vector3d p(1.0, 0.7, 2.0);
  const GaussianModel scene = Splat(p);
  SplatCamera asked;
  Expected<RenderedView> view = renderer->Render(kPose, RenderSettings{}, ReferenceRender{&scene, &asked});
  ASSERT_TRUE(view.ok()) << view.error();
  ASSERT_EQ(view->width, 64);
  ASSERT_EQ(view->height, 48);
  EXPECT_GT(asked.pinhole.width, 64);  // the covering pinhole is larger than the distorted image
  EXPECT_EQ(asked.T_world_camera.matrix(), kPose.matrix());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double total = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double alpha = view->alpha[static_cast<std::size_t>(y) * 64 + x];
      centroid += alpha * Eigen::Vector2d(x, y);
      total += alpha;
    }
  ASSERT_GT(total, 0.5);
  centroid /= total;
  const Eigen::Vector2d expected = *model.Project(p);
  EXPECT_NEAR(expected.x(), 50 * 0.5 * 0.8993 + 31.5, 0.01);
  EXPECT_NEAR(centroid.x(), expected.x(), 0.25);
  EXPECT_NEAR(centroid.y(), expected.y(), 0.25);
  EXPECT_GT((centroid - Eigen::Vector2d(56.5, 41.0)).norm(), 2.0);  // not the undistorted pinhole's place
}

TEST(CameraViewRenderer, PassesTheRenderersErrorOn) {
  const Equidistant fisheye(EquidistantIntrinsics{{64, 48, 30, 30, 31.5, 23.5}});
  Expected<CameraViewRenderer> renderer = CameraViewRenderer::Create(fisheye);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  EXPECT_TRUE(renderer->distorted());  // a fisheye is never a pinhole
  const Expected<RenderedView> view =
      renderer->Render(kPose, RenderSettings{}, [](const SplatCamera&, const RenderSettings&) {
        return Expected<RenderedView>(Status::Error("device lost"));
      });
  ASSERT_FALSE(view.ok());
  EXPECT_EQ(view.error(), "device lost");
}

}  // namespace
}  // namespace uf::splat
