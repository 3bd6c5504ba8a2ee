// The distorted-view resampler against the camera model it serves: every distorted pixel must sample the
// pinhole image where the model's own projection of that position's ray lands back on the pixel.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/types/camera_model.h"
#include "splat/views/distorted_view.h"

namespace uf::splat {
namespace {

// A pinhole view whose colour encodes the pixel position: rgb = (u / 1000, v / 1000, 0.5), depth = 1 + u.
RenderedView CoordinateView(int width, int height) {
  RenderedView view;
  view.width = width;
  view.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  view.rgb.resize(3 * n);
  view.alpha.assign(n, 1.0f);
  view.depth.resize(n);
  view.expected_depth.resize(n);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      view.rgb[3 * i + 0] = u / 1000.0f;
      view.rgb[3 * i + 1] = v / 1000.0f;
      view.rgb[3 * i + 2] = 0.5f;
      view.depth[i] = view.expected_depth[i] = 1.0f + u;
    }
  return view;
}

TEST(DistortedViewResampler, EveryPixelSamplesTheRayTheModelProjectsBackOntoIt) {
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 320, .height = 240, .fx = 300, .fy = 310, .cx = 159.5, .cy = 119.5};
  k.k1 = -0.28, k.k2 = 0.07, k.p1 = 1e-3, k.p2 = -5e-4;  // barrel distortion as in a wide-angle lens
  const PinholeRadtan model(k);
  const DistortedViewResampler resampler(model, k.pinhole);
  const PinholeIntrinsics pinhole = resampler.Pinhole(SE3()).pinhole;
  // Barrel distortion shows more than the pinhole of the same focal length: the cover is larger.
  EXPECT_GT(pinhole.width, 320);
  EXPECT_GT(pinhole.height, 240);
  const RenderedView distorted =
      resampler.Resample(CoordinateView(pinhole.width, pinhole.height), Eigen::Vector3f(0, 0, 0));
  ASSERT_EQ(distorted.width, 320);
  ASSERT_EQ(distorted.height, 240);
  double worst_px = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * 320 + x;
      ASSERT_FLOAT_EQ(distorted.alpha[i], 1.0f) << x << ", " << y;
      // Bilinear interpolation of a linear function is exact: the sampled pinhole position (u, v).
      const double u = 1000.0 * distorted.rgb[3 * i], v = 1000.0 * distorted.rgb[3 * i + 1];
      const Eigen::Vector3d ray((u - pinhole.cx) / pinhole.fx, (v - pinhole.cy) / pinhole.fy, 1.0);
      const std::optional<Eigen::Vector2d> back = model.Project(ray);
      ASSERT_TRUE(back.has_value());
      worst_px = std::max(worst_px, (*back - Eigen::Vector2d(x, y)).norm());
      // Depth: the nearest pinhole pixel, so within half a pixel of u.
      EXPECT_NEAR(distorted.depth[i], 1.0 + u, 0.5 + 1e-3);
    }
  // float colour storage of u/1000 (~1e-7 relative) and the iterative undistortion bound the error.
  EXPECT_LT(worst_px, 2e-3);
}

TEST(DistortedViewResampler, WithoutDistortionItIsAShiftOfThePinholeImage) {
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 64, .height = 48, .fx = 200, .fy = 200, .cx = 31.5, .cy = 23.5};
  const PinholeRadtan model(k);
  const DistortedViewResampler resampler(model, k.pinhole);
  const PinholeIntrinsics pinhole = resampler.Pinhole(SE3()).pinhole;
  const double shift_u = pinhole.cx - k.pinhole.cx, shift_v = pinhole.cy - k.pinhole.cy;
  EXPECT_EQ(shift_u, std::round(shift_u));  // whole-pixel shift: no interpolation blur
  const RenderedView view =
      resampler.Resample(CoordinateView(pinhole.width, pinhole.height), Eigen::Vector3f::Zero());
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * 64 + x;
      EXPECT_NEAR(1000.0 * view.rgb[3 * i], x + shift_u, 1e-3);
      EXPECT_NEAR(1000.0 * view.rgb[3 * i + 1], y + shift_v, 1e-3);
    }
}

TEST(DistortedViewResampler, RaysOutsideTheCappedPinholeImageAreBackground) {
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 64, .height = 48, .fx = 40, .fy = 40, .cx = 31.5, .cy = 23.5};  // ~77 degrees wide
  k.k1 = -0.45, k.k2 = 0.12;
  const PinholeRadtan model(k);
  const DistortedViewResampler resampler(model, k.pinhole, /*max_scale=*/1.1);
  const PinholeIntrinsics pinhole = resampler.Pinhole(SE3()).pinhole;
  EXPECT_LE(pinhole.width, static_cast<int>(1.1 * 64) + 4);
  const RenderedView view =
      resampler.Resample(CoordinateView(pinhole.width, pinhole.height), Eigen::Vector3f(0.25f, 0.5f, 0.75f));
  // The corner's ray lies beyond the cap: background colour, no alpha, no depth.
  EXPECT_FLOAT_EQ(view.rgb[0], 0.25f);
  EXPECT_FLOAT_EQ(view.rgb[2], 0.75f);
  EXPECT_FLOAT_EQ(view.alpha[0], 0.0f);
  EXPECT_TRUE(std::isinf(view.depth[0]));
  // The centre is inside.
  const std::size_t centre = 24 * 64 + 32;
  EXPECT_FLOAT_EQ(view.alpha[centre], 1.0f);
}

}  // namespace
}  // namespace uf::splat
