// Colorizer against hand-built geometry: a plane of points on pixel centres takes exactly its pixels'
// colours; bilinear sampling between pixels; points behind or outside stay uncoloured; a foreground square
// hides the background points a side-mounted LiDAR sees behind it (the z-buffer), and without the splat
// those points would take the foreground's colour; the choice among several images.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "mapping/colorizer.h"

namespace uf::mapping {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kF = 300.0, kCx = 159.5, kCy = 119.5;

PinholeRadtan TestCamera() { return PinholeRadtan({{kWidth, kHeight, kF, kF, kCx, kCy}, 0, 0, 0, 0, 0}); }

// An arbitrary camera pose, so that world and camera frames differ.
SE3 TestPose() { return SE3(SO3::Exp(Eigen::Vector3d(0.3, -0.7, 1.1)), Eigen::Vector3d(4.0, -2.0, 1.5)); }

// A colour that differs for every pixel of the test image.
Rgb PixelColor(int u, int v) {
  return {static_cast<std::uint8_t>(u % 256), static_cast<std::uint8_t>(v % 256),
          static_cast<std::uint8_t>((u / 256) * 100 + 7)};
}

Image PatternImage() {
  Image image{kWidth, kHeight, 3, std::vector<std::uint8_t>(kWidth * kHeight * 3)};
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const Rgb c = PixelColor(u, v);
      for (int k = 0; k < 3; ++k) image.pixels[(v * kWidth + u) * 3 + k] = c[k];
    }
  }
  return image;
}

// The world point at depth z (camera frame) seen at pixel (u, v) of the undistorted pinhole.
Eigen::Vector3f PointAtPixel(double u, double v, double z) {
  const Eigen::Vector3d p_cam((u - kCx) / kF * z, (v - kCy) / kF * z, z);
  return (TestPose() * p_cam).cast<float>();
}

TEST(Colorizer, PointsOnPixelCentresTakeTheirPixelsColour) {
  const PinholeRadtan camera = TestCamera();
  const Image image = PatternImage();
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector2i> pixels;
  for (int v = 0; v < kHeight; v += 7) {
    for (int u = 0; u < kWidth; u += 3) {
      points.push_back(PointAtPixel(u, v, 6.0));
      pixels.emplace_back(u, v);
    }
  }
  const std::vector<CameraView> views = {{&image, &camera, TestPose(), 0}};
  const Stamp stamp = 0;
  const auto result = Colorize(points, std::span(&stamp, 1), views);
  ASSERT_TRUE(result.ok()) << result.error();
  EXPECT_EQ(result->in_footprint, points.size());
  EXPECT_EQ(result->colored, points.size());
  EXPECT_EQ(result->occluded, 0u);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(result->colors[i].has_value()) << i;
    EXPECT_EQ(*result->colors[i], PixelColor(pixels[i].x(), pixels[i].y())) << pixels[i].transpose();
    EXPECT_EQ(result->view_index[i], 0);
  }
}

TEST(Colorizer, SamplesBilinearlyBetweenPixelCentres) {
  const Image image = PatternImage();
  // Between (10, 20), (11, 20), (10, 21), (11, 21), at a quarter and three quarters: R = 10.25, G = 20.75.
  const Eigen::Vector3f c = SampleBilinear(image, Eigen::Vector2f(10.25f, 20.75f));
  EXPECT_NEAR(c.x(), 10.25f, 1e-4f);
  EXPECT_NEAR(c.y(), 20.75f, 1e-4f);
  EXPECT_NEAR(c.z(), 7.0f, 1e-4f);
  // Clamped at the border: half a pixel outside reads the border pixel.
  EXPECT_NEAR(SampleBilinear(image, Eigen::Vector2f(-0.5f, -0.5f)).x(), 0.0f, 1e-6f);
  EXPECT_NEAR(SampleBilinear(image, Eigen::Vector2f(kWidth - 0.5f, 3.0f)).x(), float((kWidth - 1) % 256),
              1e-4f);
  // Gray images give R = G = B.
  const Image gray{2, 1, 1, {10, 30}};
  EXPECT_TRUE(SampleBilinear(gray, Eigen::Vector2f(0.5f, 0.0f)).isApprox(Eigen::Vector3f::Constant(20.0f)));
}

TEST(Colorizer, PointsBehindOrOutsideStayUncoloured) {
  const PinholeRadtan camera = TestCamera();
  const Image image = PatternImage();
  const SE3 pose = TestPose();
  const std::vector<Eigen::Vector3f> points = {
      (pose * Eigen::Vector3d(0.0, 0.0, -5.0)).cast<float>(),  // behind
      (pose * Eigen::Vector3d(10.0, 0.0, 5.0)).cast<float>(),  // far right of the image
      (pose * Eigen::Vector3d(0.0, 0.0, 5.0)).cast<float>(),   // centre: coloured
      Eigen::Vector3f(NAN, 0.0f, 0.0f),                        // not finite
  };
  const std::vector<CameraView> views = {{&image, &camera, pose, 0}};
  const Stamp stamp = 0;
  const auto result = Colorize(points, std::span(&stamp, 1), views);
  ASSERT_TRUE(result.ok());
  EXPECT_FALSE(result->colors[0].has_value());
  EXPECT_FALSE(result->colors[1].has_value());
  EXPECT_TRUE(result->colors[2].has_value());
  EXPECT_FALSE(result->colors[3].has_value());
  EXPECT_EQ(result->in_footprint, 1u);
  EXPECT_EQ(result->view_index[0], -1);
}

// A square (|x|, |y| <= kHalfSize at z = 5 m, camera frame) in front of a wall at z = 10 m, scanned by a
// LiDAR 0.8 m right of and 0.3 m below the camera on a grid of 1.5 x 6 pixel-equivalent steps (sparse rows,
// like a spinning LiDAR). The LiDAR sees wall points right of and below the square that the camera cannot
// see, and they fall between the rows of the square's points in the image.
struct SquareScene {
  std::vector<Eigen::Vector3f> points;  // world frame
  std::vector<bool> foreground;
  std::vector<bool> hidden;             // wall points the square hides from the camera (analytic)
  std::vector<double> edge_distance;    // pixel distance of the projection to the square's outline
  std::vector<Eigen::Vector2d> pixels;  // the projections
  Eigen::AlignedBox2d square_box;       // bounding box of the square's points' projections
};

// Half size 0.52 m: the outline falls at fractional pixel positions (128.3, 190.7; 88.3, 150.7), so bilinear
// sampling gives points outside it less than half of the square's colour and points inside more than half.
constexpr double kHalfSize = 0.52;

bool InSquare(double x, double y) { return std::abs(x) <= kHalfSize && std::abs(y) <= kHalfSize; }

SquareScene MakeSquareScene() {
  SquareScene scene;
  const Eigen::Vector3d lidar(0.8, 0.3, 0.0);
  for (double b = -0.35; b <= 0.35; b += 6.0 / kF) {
    for (double a = -0.5; a <= 0.5; a += 1.5 / kF) {
      const Eigen::Vector3d d(a, b, 1.0);  // ray lidar + t d reaches depth z at t = z
      const Eigen::Vector3d near = lidar + 5.0 * d;
      const bool front = InSquare(near.x(), near.y());
      const Eigen::Vector3d p = front ? near : Eigen::Vector3d(lidar + 10.0 * d);
      scene.points.push_back((TestPose() * p).cast<float>());
      scene.foreground.push_back(front);
      // The camera ray to a wall point crosses z = 5 at half its x and y.
      scene.hidden.push_back(!front && InSquare(p.x() / 2, p.y() / 2));
      const double u = kF * p.x() / p.z() + kCx, v = kF * p.y() / p.z() + kCy;
      const double du = std::abs(u - kCx) - kHalfSize * kF / 5, dv = std::abs(v - kCy) - kHalfSize * kF / 5;
      const bool inside = du <= 0 && dv <= 0;
      scene.edge_distance.push_back(inside ? std::min(-du, -dv)
                                           : std::hypot(std::max(du, 0.0), std::max(dv, 0.0)));
      scene.pixels.emplace_back(u, v);
      if (front) scene.square_box.extend(scene.pixels.back());
    }
  }
  return scene;
}

// The camera's image of the scene: red where the pixel's ray hits the square, blue elsewhere.
Image SquareImage() {
  Image image{kWidth, kHeight, 3, std::vector<std::uint8_t>(kWidth * kHeight * 3, 0)};
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const bool front = InSquare(5.0 * (u - kCx) / kF, 5.0 * (v - kCy) / kF);
      image.pixels[(v * kWidth + u) * 3 + (front ? 0 : 2)] = 255;
    }
  }
  return image;
}

TEST(Colorizer, BackgroundHiddenBehindAForegroundSquareTakesNoForegroundColour) {
  const SquareScene scene = MakeSquareScene();
  const PinholeRadtan camera = TestCamera();
  const Image image = SquareImage();
  const std::vector<CameraView> views = {{&image, &camera, TestPose(), 0}};
  const Stamp stamp = 0;
  const auto result = Colorize(scene.points, std::span(&stamp, 1), views);
  ASSERT_TRUE(result.ok());
  std::size_t hidden = 0, visible_wall = 0, visible_wall_coloured = 0;
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    const auto& color = result->colors[i];
    if (scene.foreground[i]) {
      ASSERT_TRUE(color.has_value()) << i;  // the nearest surface is always visible
      EXPECT_GT((*color)[0], (*color)[2]) << i;
    } else if (scene.hidden[i]) {
      // Between the square's outermost points and its outline (up to a row spacing, 6 pixels), hidden or
      // not is below the LiDAR's resolution; inside the box of the square's points it is not.
      if (!scene.square_box.contains(scene.pixels[i])) continue;
      ++hidden;
      EXPECT_FALSE(color.has_value()) << "hidden wall point " << i << " took a colour";
    } else {
      ++visible_wall;
      if (!color.has_value()) continue;
      ++visible_wall_coloured;
      EXPECT_GT((*color)[2], (*color)[0]) << "wall point " << i << " took the square's colour";
      if (scene.edge_distance[i] >= 1.0) {
        EXPECT_EQ(*color, (Rgb{0, 0, 255})) << i;
      }
    }
  }
  ASSERT_GT(hidden, 100u);  // the scene does test occlusion
  // Only wall points close to the square's outline may be lost to the splat.
  EXPECT_GT(visible_wall_coloured, 0.9 * visible_wall);
  EXPECT_EQ(result->occluded, result->in_footprint - result->colored);
  EXPECT_GE(result->occluded, hidden);
}

TEST(Colorizer, WithoutTheSplatSparseRowsLetTheBackgroundThrough) {
  // The same scene with a one-pixel z-buffer: the wall points between the square's rows are not hidden.
  const SquareScene scene = MakeSquareScene();
  const PinholeRadtan camera = TestCamera();
  const Image image = SquareImage();
  const std::vector<CameraView> views = {{&image, &camera, TestPose(), 0}};
  ColorizerOptions options;
  options.visibility.splat_half_width_px = 0;
  options.visibility.splat_half_height_px = 0;
  const Stamp stamp = 0;
  const auto result = Colorize(scene.points, std::span(&stamp, 1), views, options);
  ASSERT_TRUE(result.ok());
  std::size_t leaked = 0;
  for (std::size_t i = 0; i < scene.points.size(); ++i)
    leaked += scene.hidden[i] && result->colors[i].has_value();
  EXPECT_GT(leaked, 50u);
}

TEST(Colorizer, PrefersTheClosestImageInTimeThenTheMostFrontalView) {
  const PinholeRadtan camera = TestCamera();
  const Image red{kWidth, kHeight, 1, std::vector<std::uint8_t>(kWidth * kHeight, 200)};
  const Image dark{kWidth, kHeight, 1, std::vector<std::uint8_t>(kWidth * kHeight, 50)};
  const Image mid{kWidth, kHeight, 1, std::vector<std::uint8_t>(kWidth * kHeight, 120)};
  const SE3 pose = TestPose();
  // One point on the optical axis of `pose`; a second camera turned 10 degrees sees it off-axis.
  const std::vector<Eigen::Vector3f> points = {(pose * Eigen::Vector3d(0, 0, 8)).cast<float>()};
  const SE3 turned = pose * SE3(SO3::Exp(Eigen::Vector3d(0, 0.17, 0)), Eigen::Vector3d::Zero());
  const Stamp t = 1'000'000'000;
  const std::vector<Stamp> stamps = {t};
  // Same time: the frontal view wins whatever the order.
  std::vector<CameraView> views = {{&dark, &camera, turned, t}, {&red, &camera, pose, t}};
  auto result = Colorize(points, stamps, views);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->view_index[0], 1);
  EXPECT_EQ((*result->colors[0])[0], 200);
  // A closer time wins over a more frontal view; one beyond max_time_difference_s is never used.
  views = {{&red, &camera, pose, t + 200'000'000},
           {&dark, &camera, turned, t + 10'000'000},
           {&mid, &camera, pose, t - 900'000'000}};
  result = Colorize(points, stamps, views);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->view_index[0], 1);
  views = {{&mid, &camera, pose, t - 900'000'000}};
  result = Colorize(points, stamps, views);
  ASSERT_TRUE(result.ok());
  EXPECT_FALSE(result->colors[0].has_value());
  EXPECT_EQ(result->in_footprint, 0u);
}

TEST(Colorizer, RejectsBadOptionsAndImages) {
  ColorizerOptions options;
  options.visibility.depth_tolerance_m = -1;
  EXPECT_EQ(ValidateColorizerOptions(options).message(),
            "colorizer.visibility.depth_tolerance_m: must be finite and >= 0, got -1");
  options = {};
  options.visibility.splat_half_height_px = 40;
  EXPECT_EQ(ValidateColorizerOptions(options).message(),
            "colorizer.visibility.splat_half_height_px: must be -1 (automatic) or in [0, 32], got 40");
  options = {};
  options.max_time_difference_s = 0;
  EXPECT_FALSE(ValidateColorizerOptions(options).ok());
  EXPECT_TRUE(ValidateColorizerOptions({}).ok());

  const PinholeRadtan camera = TestCamera();
  const Image small{10, 10, 3, std::vector<std::uint8_t>(300)};
  const std::vector<CameraView> views = {{&small, &camera, SE3(), 0}};
  const std::vector<Eigen::Vector3f> points = {Eigen::Vector3f(0, 0, 1)};
  const Stamp stamp = 0;
  const auto result = Colorize(points, std::span(&stamp, 1), views);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error(), "view 0: image: size 10x10 differs from the camera's 320x240");
}

}  // namespace
}  // namespace uf::mapping
