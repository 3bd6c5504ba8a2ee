// Training images: area resizing against hand-computed averages, intrinsics that keep the image edges,
// undistortion through the camera model, LiDAR depth with a z-buffer (and resized as it would have been
// rendered), whole views resized, 8-bit conversion, the pinhole of each camera model.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/views/training_images.h"

namespace uf::splat {
namespace {

TEST(TrainingImages, HalvingAveragesEachTwoByTwoBlock) {
  // 4 x 2, one channel: rows 0..3 and 10..13.
  const std::vector<float> image = {0, 1, 2, 3, 10, 11, 12, 13};
  const std::vector<float> half = ResizeArea(image, 4, 2, 1, 2, 1);
  ASSERT_EQ(half.size(), 2u);
  EXPECT_FLOAT_EQ(half[0], (0 + 1 + 10 + 11) / 4.0f);
  EXPECT_FLOAT_EQ(half[1], (2 + 3 + 12 + 13) / 4.0f);
}

TEST(TrainingImages, FractionalRatiosWeighPixelsByTheAreaTheyOverlap) {
  // 3 -> 2 pixels: target pixel 0 covers source [0, 1.5): all of pixel 0 and half of pixel 1.
  const std::vector<float> image = {3, 6, 9};
  const std::vector<float> out = ResizeArea(image, 3, 1, 1, 2, 1);
  EXPECT_FLOAT_EQ(out[0], (3 + 0.5f * 6) / 1.5f);
  EXPECT_FLOAT_EQ(out[1], (0.5f * 6 + 9) / 1.5f);
  // Three channels stay separate.
  const std::vector<float> rgb = {1, 2, 3, 5, 6, 7};
  const std::vector<float> one = ResizeArea(rgb, 2, 1, 3, 1, 1);
  EXPECT_FLOAT_EQ(one[0], 3);
  EXPECT_FLOAT_EQ(one[1], 4);
  EXPECT_FLOAT_EQ(one[2], 5);
}

TEST(TrainingImages, ScaledIntrinsicsKeepTheImageEdgesInPlace) {
  const PinholeIntrinsics camera{640, 480, 500, 510, 319.5, 239.5};
  const PinholeIntrinsics half = ScalePinhole(camera, 320, 240);
  EXPECT_DOUBLE_EQ(half.fx, 250);
  EXPECT_DOUBLE_EQ(half.fy, 255);
  EXPECT_DOUBLE_EQ(half.cx, 159.5);  // the centre of the image stays the centre
  EXPECT_DOUBLE_EQ(half.cy, 119.5);
  // A ray through the left edge of pixel 0 (u = -0.5) goes through the left edge of the resized image.
  const double x = (-0.5 - camera.cx) / camera.fx;
  EXPECT_NEAR(half.fx * x + half.cx, -0.5, 1e-12);
}

TEST(TrainingImages, UndistortionSamplesTheDistortedImageWhereTheModelProjectsEachRay) {
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 40, .height = 30, .fx = 40, .fy = 40, .cx = 19.5, .cy = 14.5};
  k.k1 = -0.2, k.p1 = 0.01;
  const PinholeRadtan model(k);
  ASSERT_TRUE(IsDistorted(model));
  // A ramp linear in the distorted pixel's u: bilinear sampling reproduces it exactly inside the image.
  std::vector<float> rgb(3 * 40 * 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c) rgb[3 * (y * 40 + x) + c] = (c + 1) * x / 100.0f + y / 1000.0f;
  const PinholeIntrinsics pinhole = *PinholeOf(model);
  const std::vector<float> out = Undistort(rgb, model, pinhole);
  int checked = 0;
  for (int y = 0; y < 30; y += 3)
    for (int x = 0; x < 40; x += 3) {
      const auto p = model.Project(Eigen::Vector3d((x - 19.5) / 40, (y - 14.5) / 40, 1));
      ASSERT_TRUE(p.has_value());
      if (p->x() < 0 || p->y() < 0 || p->x() > 39 || p->y() > 29) continue;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out[3 * (y * 40 + x) + c], (c + 1) * p->x() / 100 + p->y() / 1000, 1e-5) << x << " " << y;
      ++checked;
    }
  EXPECT_GT(checked, 80);
  const PinholeRadtan plain(PinholeRadtanIntrinsics{{40, 30, 40, 40, 19.5, 14.5}});
  EXPECT_FALSE(IsDistorted(plain));
}

TEST(TrainingImages, CoverageMarksThePixelsUndistortionCannotFill) {
  // Pincushion distortion: the pinhole view's corners see rays that land outside the distorted image.
  PinholeRadtanIntrinsics k;
  k.pinhole = {.width = 40, .height = 30, .fx = 30, .fy = 30, .cx = 19.5, .cy = 14.5};
  k.k1 = 0.4;
  const PinholeRadtan model(k);
  const PinholeIntrinsics pinhole = *PinholeOf(model);
  const std::vector<std::uint8_t> coverage = UndistortedCoverage(model, pinhole);
  // An all-white image undistorts to 1 exactly where the coverage says the image fills the pixel.
  const std::vector<float> white(3 * 40 * 30, 1.0f);
  const std::vector<float> out = Undistort(white, model, pinhole);
  int uncovered = 0;
  for (std::size_t p = 0; p < coverage.size(); ++p) {
    EXPECT_EQ(coverage[p], out[3 * p] > 0.5f ? 1 : 0) << "pixel " << p;
    uncovered += coverage[p] == 0;
  }
  EXPECT_EQ(coverage[0], 0);             // a corner
  EXPECT_EQ(coverage[15 * 40 + 20], 1);  // the centre
  EXPECT_GT(uncovered, 20);
  EXPECT_LT(uncovered, 40 * 30 / 2);
}

TEST(TrainingImages, AResizedMaskMasksEveryPixelThatOverlapsAMaskedOne) {
  // 6 x 2 -> 3 x 1 (2 x 2 blocks) and 6 x 2 -> 4 x 1 (1.5 px footprints).
  std::vector<std::uint8_t> mask(12, 1);
  mask[2] = 0;  // (2, 0)
  EXPECT_EQ(ResizeMask(mask, 6, 2, 3, 1), (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(ResizeMask(mask, 6, 2, 4, 1), (std::vector<std::uint8_t>{1, 0, 1, 1}));
  mask[2] = 1, mask[3] = 0;  // (3, 0): overlapped by the 2nd and 3rd of 4 footprints [1.5, 3) and [3, 4.5)
  EXPECT_EQ(ResizeMask(mask, 6, 2, 4, 1), (std::vector<std::uint8_t>{1, 1, 0, 1}));
}

TEST(TrainingImages, LidarDepthKeepsTheNearestPointPerPixel) {
  SplatCamera camera;
  camera.pinhole = {.width = 8, .height = 6, .fx = 4, .fy = 4, .cx = 3.5, .cy = 2.5};
  // The camera at (0, 0, -1), its axes the world's.
  camera.T_world_camera = SE3(SO3(), Eigen::Vector3d(0, 0, -1));
  const std::vector<Eigen::Vector3f> points = {
      {1, 0.5f, 3},   // t = (1, 0.5, 4): u = 4 * 1 / 4 + 3.5 = 4.5 -> 5 (round half away), v = 3
      {2, 1, 7},      // t = (2, 1, 8): the same pixel, farther
      {0, 0, -1.1f},  // behind the camera
      {100, 0, 1}};   // outside the image
  const std::vector<float> depth = ProjectDepth(points, camera);
  ASSERT_EQ(depth.size(), 48u);
  EXPECT_FLOAT_EQ(depth[3 * 8 + 5], 4.0f);
  int filled = 0;
  for (float d : depth) filled += d > 0;
  EXPECT_EQ(filled, 1);
}

TEST(TrainingImages, AResizedDepthKeepsTheNearestDepthLandingInEachPixel) {
  // 4 x 2 -> 2 x 1: source centres x = 0..3 land in round(0.5 (x + 0.5) - 0.5) = 0, 0, 1, 1 (round half away
  // from zero: 0.25 -> 0, 0.75 -> 1), rows 0 and 1 in row 0.
  const std::vector<float> depth = {5, 0, 0, 9,  //
                                    3, 7, 0, 0};
  EXPECT_EQ(ResizeDepth(depth, 4, 2, 2, 1), (std::vector<float>{3, 9}));
  // Nothing landing: 0 (no depth), not the mean of the empty pixels.
  EXPECT_EQ(ResizeDepth(std::vector<float>(8, 0.0f), 4, 2, 2, 1), (std::vector<float>{0, 0}));
  // 5 -> 3: centres 0..4 land in round(0.6 (x + 0.5) - 0.5) = round(-0.2, 0.4, 1, 1.6, 2.2) = 0, 0, 1, 2, 2.
  EXPECT_EQ(ResizeDepth(std::vector<float>{4, 6, 2, 8, 0}, 5, 1, 3, 1), (std::vector<float>{4, 2, 8}));
}

TEST(TrainingImages, AResizedViewCarriesItsDepthMaskAndIntrinsicsToTheNewSize) {
  TrainingView view;
  view.camera.pinhole = {.width = 4, .height = 2, .fx = 4, .fy = 4, .cx = 1.5, .cy = 0.5};
  view.camera.T_world_camera = SE3(SO3::Exp(Eigen::Vector3d(0.1, 0.2, 0.3)), Eigen::Vector3d(1, 2, 3));
  view.rgb = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3,  //
              4, 4, 4, 5, 5, 5, 6, 6, 6, 7, 7, 7};
  view.depth = {5, 0, 0, 9, 3, 7, 0, 0};
  view.mask = {1, 1, 1, 0, 1, 1, 1, 1};
  const TrainingView half = ResizeView(view, 2, 1);
  EXPECT_EQ(half.rgb, (std::vector<float>{2.5f, 2.5f, 2.5f, 4.5f, 4.5f, 4.5f}));
  EXPECT_EQ(half.depth, (std::vector<float>{3, 9}));
  EXPECT_EQ(half.mask, (std::vector<std::uint8_t>{1, 0}));
  const PinholeIntrinsics expected = ScalePinhole(view.camera.pinhole, 2, 1);
  EXPECT_EQ(half.camera.pinhole.width, 2);
  EXPECT_EQ(half.camera.pinhole.height, 1);
  EXPECT_DOUBLE_EQ(half.camera.pinhole.fx, expected.fx);
  EXPECT_DOUBLE_EQ(half.camera.pinhole.cx, expected.cx);
  EXPECT_DOUBLE_EQ(half.camera.pinhole.cy, expected.cy);
  EXPECT_TRUE(half.camera.T_world_camera.matrix().isApprox(view.camera.T_world_camera.matrix()));
  // Without depth and mask they stay empty (every pixel counts, no depth term).
  view.depth.clear(), view.mask.clear();
  const TrainingView plain = ResizeView(view, 2, 1);
  EXPECT_TRUE(plain.depth.empty());
  EXPECT_TRUE(plain.mask.empty());
}

TEST(TrainingImages, GrayImagesBecomeGreyRgb) {
  Image gray;
  gray.width = 2, gray.height = 1, gray.channels = 1, gray.pixels = {0, 255};
  EXPECT_EQ(ToRgbFloat(gray), (std::vector<float>{0, 0, 0, 1, 1, 1}));
  Image rgb;
  rgb.width = 1, rgb.height = 1, rgb.channels = 3, rgb.pixels = {51, 102, 255};
  EXPECT_EQ(ToRgbFloat(rgb), (std::vector<float>{0.2f, 0.4f, 1.0f}));
}

}  // namespace
}  // namespace uf::splat
