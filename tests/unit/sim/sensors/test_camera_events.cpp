// Tests of the simulated camera's events (darkness, exposure changes, occluder), noise, determinism,
// configuration errors, and its measured speed.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <vector>

#include "odometry/sim/sensors/camera_renderer.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "tests/unit/sim/sensors/camera_test_support.h"
#include "tests/unit/sim/sensors/sensor_test_scenes.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf::sim {
namespace {

using namespace camera_test;  // NOLINT: the helpers of these tests

// ---- Events ----

struct EventFixture {
  Scene scene = test::BoxRoomScene();
  RayCaster caster = std::move(RayCaster::Create(scene)).value();
  TrajectorySpline spline = StaticTrajectory(SE3(SO3(), Eigen::Vector3d(-12, -2, 0.5)));
  CameraConfig config = [] {
    CameraConfig c;
    c.pinhole = {.width = 160, .height = 120, .fx = 100, .fy = 100, .cx = 79.5, .cy = 59.5};
    c.noise_std_dn = 0.0;
    return c;
  }();
};

TEST(CameraRenderer, DarknessDimsTenfoldAndTriplesTheNoise) {
  EventFixture f;
  f.config.darkness = {{2 * kSecond, 4 * kSecond}};
  const CameraRenderer renderer = MakeRenderer(f.config, f.caster, f.spline, LookAlongX());
  const double ratio =
      MeanLinear(RenderImage(renderer, kSecond)) / MeanLinear(RenderImage(renderer, 3 * kSecond));
  EXPECT_NEAR(ratio, 10.0, 0.5);

  // Noise: the difference of two seeds' images has variance 2 (sigma^2 + 1/12), 1/12 from the rounding.
  f.config.noise_std_dn = 2.0;
  const CameraRenderer a = MakeRenderer(f.config, f.caster, f.spline, LookAlongX(), 1);
  const CameraRenderer b = MakeRenderer(f.config, f.caster, f.spline, LookAlongX(), 2);
  const auto noise_std = [&](Stamp t) {
    const Image x = RenderImage(a, t), y = RenderImage(b, t);
    double sum = 0.0, sum_squares = 0.0;
    for (std::size_t i = 0; i < x.pixels.size(); ++i) {
      const double d = double(x.pixels[i]) - double(y.pixels[i]);
      sum += d, sum_squares += d * d;
    }
    const double n = static_cast<double>(x.pixels.size());
    return std::sqrt((sum_squares / n - (sum / n) * (sum / n)) / 2.0 - 1.0 / 12.0);
  };
  EXPECT_NEAR(noise_std(kSecond), 2.0, 0.06);
  EXPECT_NEAR(noise_std(3 * kSecond), 6.0, 0.18);
}

TEST(CameraRenderer, ExposureChangeScalesTheBrightnessInsideItsWindowOnly) {
  EventFixture f;
  f.config.exposure_changes = {{{2 * kSecond, 4 * kSecond}, 0.5}, {{3 * kSecond, 5 * kSecond}, 0.8}};
  const CameraRenderer renderer = MakeRenderer(f.config, f.caster, f.spline, LookAlongX());
  const Image before = RenderImage(renderer, kSecond);
  const double mean = MeanLinear(before);
  EXPECT_NEAR(mean / MeanLinear(RenderImage(renderer, 2 * kSecond + 1)), 2.0, 0.05);
  EXPECT_NEAR(mean / MeanLinear(RenderImage(renderer, 3 * kSecond)), 2.5,
              0.07);  // overlapping: gains multiply
  EXPECT_NEAR(mean / MeanLinear(RenderImage(renderer, 4 * kSecond)), 1.25, 0.03);
  EXPECT_EQ(RenderImage(renderer, 5 * kSecond).pixels, before.pixels);  // window end is exclusive
}

TEST(CameraRenderer, OccluderCoversAThirdOfTheImageAndSlidesAcrossIt) {
  EventFixture f;
  f.config.occlusions = {{2 * kSecond, 4 * kSecond}};
  const CameraRenderer renderer = MakeRenderer(f.config, f.caster, f.spline, LookAlongX());
  const cv::Mat clear = LinearGray(RenderImage(renderer, kSecond));
  std::vector<double> mean_columns;
  for (Stamp t : {2 * kSecond, 3 * kSecond, 4 * kSecond - 1}) {
    const cv::Mat occluded = LinearGray(RenderImage(renderer, t));
    int dark = 0;
    double column_sum = 0.0;
    for (int v = 0; v < clear.rows; ++v) {
      for (int u = 0; u < clear.cols; ++u) {
        if (occluded.at<float>(v, u) < 0.5f * clear.at<float>(v, u)) ++dark, column_sum += u;
      }
    }
    EXPECT_NEAR(double(dark) / double(clear.total()), 1.0 / 3.0, 0.02);
    mean_columns.push_back(column_sum / dark);
  }
  // From the left side, through the middle, to the right side.
  EXPECT_NEAR(mean_columns[0], 160.0 / 6.0 + 160.0 / 30.0 - 0.5, 2.0);
  EXPECT_NEAR(mean_columns[1], 79.5, 2.0);
  EXPECT_NEAR(mean_columns[2], 160.0 * 5.0 / 6.0 - 160.0 / 30.0 - 0.5, 2.0);
}

TEST(CameraRenderer, PassingPanelCoversHalfTheImageAndCarriesItsTextureWithIt) {
  EventFixture f;
  f.config.passing_panels = {{2 * kSecond, 4 * kSecond}};
  const CameraRenderer renderer = MakeRenderer(f.config, f.caster, f.spline, LookAlongX());
  const cv::Mat clear = LinearGray(RenderImage(renderer, kSecond));
  // Progress 0.4 and 0.5: the left edge at x' = 16 and 40 (-W/2 + 1.5 W progress), the band W/2 = 80 wide.
  const cv::Mat a = LinearGray(RenderImage(renderer, 2 * kSecond + FromSeconds(0.8)));
  const cv::Mat b = LinearGray(RenderImage(renderer, 3 * kSecond));
  int changed = 0, same_after_shift = 0, compared = 0;
  for (int v = 0; v < clear.rows; ++v) {
    for (int u = 0; u < clear.cols; ++u) {
      const bool inside = u >= 16 && u < 96;
      if (!inside) {
        EXPECT_EQ(a.at<float>(v, u), clear.at<float>(v, u)) << u << "," << v;
        continue;
      }
      changed += std::abs(a.at<float>(v, u) - clear.at<float>(v, u)) > 1e-3f;
      // The texture moved 24 px to the right with the panel.
      ++compared;
      same_after_shift += std::abs(b.at<float>(v, u + 24) - a.at<float>(v, u)) <= 0.01f;
    }
  }
  EXPECT_GT(changed, compared * 9 / 10);
  EXPECT_EQ(same_after_shift, compared);
  // Before it enters and after it leaves, the view is clear.
  EXPECT_EQ(RenderImage(renderer, 2 * kSecond).pixels, RenderImage(renderer, kSecond).pixels);
  EXPECT_EQ(RenderImage(renderer, 4 * kSecond).pixels, RenderImage(renderer, kSecond).pixels);
}

// ---- Determinism ----

TEST(CameraRenderer, OutputDependsOnlyOnSeedAndTimeNotOnThreads) {
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = uf::test::RandomSpline(5, 10, kSecond / 2);
  CameraConfig config;
  config.pinhole = {.width = 120, .height = 90, .fx = 80, .fy = 80, .cx = 59.5, .cy = 44.5};
  config.supersampling = 2;
  config.noise_std_dn = 1.5;
  const Stamp t = spline.begin() + FromSeconds(1.7);
  std::vector<std::uint8_t> reference;
  for (int threads : {1, 2, 3, 7}) {
    config.threads = threads;
    const CameraRenderer renderer = MakeRenderer(config, *caster, spline, LookAlongX(), 42);
    auto frame = renderer.Render(t, 2);
    ASSERT_TRUE(frame.ok());
    EXPECT_EQ(frame->stamp, t);
    EXPECT_EQ(frame->camera, 2);
    EXPECT_TRUE(frame->encoded.empty());
    EXPECT_EQ(frame->image.channels, 3);
    ASSERT_EQ(frame->image.pixels.size(), 120u * 90u * 3u);
    if (reference.empty()) reference = frame->image.pixels;
    EXPECT_EQ(frame->image.pixels, reference) << threads << " threads";
    EXPECT_EQ(RenderImage(renderer, t).pixels, reference);  // rendering twice
  }
  const CameraRenderer other_seed = MakeRenderer(config, *caster, spline, LookAlongX(), 43);
  EXPECT_NE(RenderImage(other_seed, t).pixels, reference);
  config.noise_std_dn = 0.0;  // without noise, the seed does not matter
  EXPECT_EQ(RenderImage(MakeRenderer(config, *caster, spline, LookAlongX(), 1), t).pixels,
            RenderImage(MakeRenderer(config, *caster, spline, LookAlongX(), 2), t).pixels);
}

// ---- Configuration errors ----

TEST(CameraRenderer, BadConfigsGiveErrorsNamingTheField) {
  EXPECT_TRUE(ValidateCameraConfig(CameraConfig{}).ok());
  struct Case {
    void (*mutate)(CameraConfig&);
    const char* expected;
  };
  const Case cases[] = {
      {[](CameraConfig& c) { c.pinhole.width = 0; }, "camera.width: must be in [1, 16384], got 0"},
      {[](CameraConfig& c) { c.pinhole.height = 20000; }, "camera.height"},
      {[](CameraConfig& c) { c.pinhole.fx = 0; }, "camera.fx: must be positive and finite, got 0"},
      {[](CameraConfig& c) { c.pinhole.fy = std::nan(""); }, "camera.fy"},
      {[](CameraConfig& c) { c.pinhole.cx = 700; },
       "camera.cx: must be inside the image [-0.5, 640 - 0.5], got 700"},
      {[](CameraConfig& c) { c.pinhole.cy = -1; }, "camera.cy"},
      {[](CameraConfig& c) { c.k2 = INFINITY; }, "camera.k2: must be finite, got inf"},
      {[](CameraConfig& c) { c.rate_hz = -5; }, "camera.rate_hz: must be in (0, 1000], got -5"},
      {[](CameraConfig& c) { c.noise_std_dn = -1; }, "camera.noise_std_dn"},
      {[](CameraConfig& c) { c.supersampling = 0; }, "camera.supersampling: must be in [1, 16], got 0"},
      {[](CameraConfig& c) { c.sun_direction_world.setZero(); }, "camera.sun_direction_world"},
      {[](CameraConfig& c) { c.ambient = 1.5; }, "camera.ambient: must be in [0, 1], got 1.5"},
      {[](CameraConfig& c) { c.exposure = 0; }, "camera.exposure"},
      {[](CameraConfig& c) {
         c.darkness = {{0, kSecond}, {3 * kSecond, 2 * kSecond}};
       },
       "camera.darkness[1]: end must be after begin, got [3.000000000, 2.000000000] s"},
      {[](CameraConfig& c) {
         c.exposure_changes = {{{0, kSecond}, -2.0}};
       },
       "camera.exposure_changes[0].gain: must be positive and finite, got -2"},
      {[](CameraConfig& c) {
         c.occlusions = {{kSecond, kSecond}};
       },
       "camera.occlusions[0]"},
      {[](CameraConfig& c) { c.threads = -1; }, "camera.threads"},
  };
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = StaticTrajectory();
  for (const Case& test_case : cases) {
    CameraConfig config;
    test_case.mutate(config);
    const Status status = ValidateCameraConfig(config);
    ASSERT_FALSE(status.ok()) << test_case.expected;
    EXPECT_NE(status.message().find(test_case.expected), std::string::npos) << status.message();
    auto renderer = CameraRenderer::Create(config, *caster, spline, SE3(), 1);
    ASSERT_FALSE(renderer.ok());
    EXPECT_EQ(renderer.error(), status.message());
  }
  // A distortion that folds over inside the image (r (1 + k1 r^2) peaks at r^2 = 1/(-3 k1) = 0.67 while the
  // image corners reach r^2 = 2.5), and a non-finite extrinsic.
  CameraConfig folded;
  folded.pinhole.fx = folded.pinhole.fy = 200;
  folded.k1 = -0.5;
  auto renderer = CameraRenderer::Create(folded, *caster, spline, SE3(), 1);
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.error().find("camera distortion (k1 -0.5"), std::string::npos) << renderer.error();
  auto bad_extrinsic =
      CameraRenderer::Create(CameraConfig{}, *caster, spline, SE3(SO3(), Eigen::Vector3d(NAN, 0, 0)), 1);
  ASSERT_FALSE(bad_extrinsic.ok());
  EXPECT_NE(bad_extrinsic.error().find("T_body_camera"), std::string::npos);
}

// ---- Speed (recorded, not asserted) ----

TEST(CameraRenderer, RendersFullSizeFramesAndRecordsTheRate) {
  const Scene scene = test::BoxRoomScene();
  auto caster = RayCaster::Create(scene);
  ASSERT_TRUE(caster.ok());
  const TrajectorySpline spline = uf::test::RandomSpline(9, 12, kSecond / 2);
  CameraConfig config;  // 640 x 480, supersampling 1, all cores
  const CameraRenderer renderer = MakeRenderer(config, *caster, spline, LookAlongX(), 3);
  constexpr int kFrames = 10;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kFrames; ++i) {
    const Image image = RenderImage(renderer, spline.begin() + i * kSecond / 10);
    ASSERT_EQ(image.pixels.size(), 640u * 480u * 3u);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  uf::test::RecordFigure("camera_frames_per_second_640x480", kFrames / seconds);
  std::printf("camera 640x480: %.1f frames/s\n", kFrames / seconds);
}

}  // namespace
}  // namespace uf::sim
