#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "odometry/estimator/visual/feature_tracker.h"
#include "tests/unit/estimator/visual/simulated_camera.h"

namespace uf::estimator {
namespace {

constexpr Stamp kFramePeriod = 100'000'000;  // 10 Hz, the simulated camera's rate

double Median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

Image Filled(int width, int height, std::uint8_t value) {
  return {width, height, 1, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height, value)};
}

// Tracks on simulated frames land where the scene point first tracked projects in the later frames.
TEST(FeatureTracker, TracksFollowTheTrueProjectionsOfScenePoints) {
  const auto camera = test::SimulatedCamera::Create("urban", 8.0, 3);
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker) << tracker.error();

  std::map<long, std::optional<Eigen::Vector3d>> points;  // per track: the scene point of its first pixel
  std::vector<double> errors;
  double features = 0, occupancy = 0;
  const int frames = 12;
  for (int k = 0; k < frames; ++k) {
    const Stamp t = camera->begin() + 2'000'000'000 + k * kFramePeriod;
    auto frame = tracker->Track(t, camera->Render(t));
    ASSERT_TRUE(frame) << frame.error();
    EXPECT_TRUE(frame->stats.warning.empty()) << frame->stats.warning;
    features += frame->stats.features;
    occupancy += frame->stats.grid_occupancy;
    for (const TrackedFeature& f : frame->features) {
      if (f.length == 1) {
        points[f.id] = camera->PointAt(t, f.pixel);
        continue;
      }
      const std::optional<Eigen::Vector3d>& point = points.at(f.id);
      if (!point) continue;  // the sky
      const std::optional<Eigen::Vector2d> truth = camera->PixelOf(t, *point);
      ASSERT_TRUE(truth.has_value());
      errors.push_back((*truth - f.pixel).norm());
    }
  }
  ASSERT_GT(errors.size(), 500u);
  EXPECT_LT(Median(errors), 0.5) << errors.size() << " tracked observations";
  EXPECT_GT(features / frames, 120.0);  // of the 150 wanted
  EXPECT_GT(occupancy / frames, 0.5);   // spread over the image, not clustered
}

// A texture of known spectrum sampled at pixel centres and moved by a known sub-pixel shift per frame. Its
// waves lie within the pixels' band (at most 0.5 cycles per pixel along each axis): coarse ones (0.05-0.12
// cycles per pixel) and fine ones (0.36-0.47). With `aliased` the fine waves are the aliases of finer waves
// of the scene, one cycle per pixel further along x or y (0.62-0.67): the first frame is the same image, but
// as the scene moves they move against it.
Image WaveTexture(int width, int height, const Eigen::Vector2d& shift, bool aliased) {
  struct Wave {
    double fx, fy, amplitude, phase;
    int wrap_x, wrap_y;  // the scene's wave is (fx + wrap_x, fy + wrap_y) when aliased
  };
  static const Wave waves[] = {{0.043, 0.021, 28, 0.3, 0, 0},  {-0.031, 0.067, 28, 1.9, 0, 0},
                               {0.088, -0.052, 22, 4.1, 0, 0}, {0.071, 0.094, 22, 2.6, 0, 0},
                               {-0.39, 0.17, 14, 0.7, 1, 0},   {-0.22, -0.42, 14, 5.2, 0, 1},
                               {0.12, -0.34, 12, 3.3, 0, 1}};
  Image image{width, height, 1, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double value = 128;
      for (const Wave& w : waves) {
        const double fx = w.fx + (aliased ? w.wrap_x : 0), fy = w.fy + (aliased ? w.wrap_y : 0);
        value += w.amplitude * std::cos(2 * M_PI * (fx * (x - shift.x()) + fy * (y - shift.y())) + w.phase);
      }
      image.pixels[static_cast<std::size_t>(y) * width + x] =
          static_cast<std::uint8_t>(std::clamp(value, 0.0, 255.0));
    }
  return image;
}

// The mean error of the tracks' frame-to-frame motion against the true shift, px.
double MeanFlowError(double smoothing_sigma_px, bool aliased) {
  const PinholeRadtan camera(
      {.pinhole = {.width = 320, .height = 240, .fx = 300, .fy = 300, .cx = 160, .cy = 120}});
  FeatureTrackerConfig config;
  config.smoothing_sigma_px = smoothing_sigma_px;
  config.min_distance_px = 15;
  auto tracker = FeatureTracker::Create(camera, config);
  EXPECT_TRUE(tracker) << tracker.error();
  const Eigen::Vector2d step(0.37, 0.23);  // px per frame
  double sum = 0;
  int n = 0;
  for (int k = 0; k < 10 && tracker; ++k) {
    auto frame = tracker->Track(1 + k * kFramePeriod, WaveTexture(320, 240, k * step, aliased));
    EXPECT_TRUE(frame) << frame.error();
    if (!frame) break;
    for (const TrackedFeature& f : frame->features)
      if (f.length > 1) sum += (f.pixel - f.previous_pixel - step).norm(), ++n;
  }
  EXPECT_GT(n, 300);
  return sum / std::max(n, 1);
}

// A sensor that samples the scene at points aliases its finest texture, and the aliases move against the
// scene. Smoothing (0.8 px, as configs/run-sim.yaml sets for the simulator's camera) damps them (a Gaussian
// passes exp(-2 pi^2 sigma^2 f^2) of a wave of f cycles per pixel: 0.06-0.19 of these) far more than the
// coarse waves (at least 0.84), so Lucas-Kanade follows the scene. Measured: 0.34 px sharp, 0.026 px
// smoothed; the same first image with the fine waves moving with the scene 0.066 and 0.047 px.
TEST(FeatureTracker, SmoothingKeepsTracksOnAliasedTextureWithTheScene) {
  const double sharp = MeanFlowError(0, true), smoothed = MeanFlowError(0.8, true);
  const double sharp_clean = MeanFlowError(0, false), smoothed_clean = MeanFlowError(0.8, false);
  EXPECT_GT(sharp, 3 * sharp_clean);  // the aliases are what the sharp tracks follow
  EXPECT_LT(smoothed, 0.25 * sharp);
  EXPECT_LT(smoothed, 0.1);
  EXPECT_LT(smoothed_clean, 0.1);
}

TEST(FeatureTracker, AStillCameraKeepsEveryTrackWithoutParallax) {
  const auto camera = test::SimulatedCamera::Create("warehouse", 4.0, 1);
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker);
  const Image image = camera->Render(camera->begin() + 500'000'000);
  auto first = tracker->Track(1000, image);
  ASSERT_TRUE(first);
  EXPECT_TRUE(first->stats.keyframe);
  EXPECT_EQ(first->stats.tracked, 0);
  EXPECT_GT(first->stats.detected, 50);
  for (int k = 1; k <= 3; ++k) {
    auto again = tracker->Track(1000 + k * kFramePeriod, image);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->stats.tracked, first->stats.features);
    EXPECT_DOUBLE_EQ(again->stats.tracked_ratio, 1.0);
    EXPECT_EQ(again->stats.detected, 0);
    EXPECT_LT(again->stats.parallax_px, 0.01);
    EXPECT_FALSE(again->stats.keyframe);
    for (const TrackedFeature& f : again->features) {
      EXPECT_EQ(f.length, k + 1);
      EXPECT_LT((f.pixel - f.previous_pixel).norm(), 0.01);
      EXPECT_LT(f.velocity.norm(), 1e-3);
    }
  }
}

TEST(FeatureTracker, PoorFramesAreTrackedWithAWarningAndTrackingResumes) {
  const auto camera = test::SimulatedCamera::Create("urban", 6.0, 2);
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker);
  const int w = camera->model().width(), h = camera->model().height();
  Stamp t = camera->begin() + 1'000'000'000;
  ASSERT_TRUE(tracker->Track(t, camera->Render(t)));
  struct Case {
    Image image;
    const char* warning;
  };
  const std::vector<Case> cases = {
      {Filled(w, h, 0), "dark"}, {Filled(w, h, 255), "saturated"}, {Filled(w, h, 128), "textureless"}};
  for (const Case& c : cases) {
    t += kFramePeriod;
    auto frame = tracker->Track(t, c.image);
    ASSERT_TRUE(frame) << frame.error();
    EXPECT_NE(frame->stats.warning.find(c.warning), std::string::npos) << frame->stats.warning;
    EXPECT_EQ(frame->stats.features, 0) << c.warning;
    for (const TrackedFeature& f : frame->features) EXPECT_TRUE(f.pixel.allFinite());
  }
  t += kFramePeriod;
  auto resumed = tracker->Track(t, camera->Render(t));
  ASSERT_TRUE(resumed);
  EXPECT_TRUE(resumed->stats.warning.empty());
  EXPECT_GT(resumed->stats.detected, 100);
  EXPECT_TRUE(resumed->stats.keyframe);  // nothing in common with the last keyframe
}

// The simulator's scripted exposure change (gain 0.4 over 3-4 s) and darkness (illumination x 0.1, noise
// x 3 over 5-6 s): Lucas-Kanade matches raw intensities, so without the exposure normalization every track
// is lost at each of the four transitions; with it most survive.
TEST(FeatureTracker, TracksSurviveExposureAndIlluminationChanges) {
  const Stamp t0 = 1'700'000'000'000'000'000;  // the simulator's default start
  const auto camera = test::SimulatedCamera::Create("urban", 8.0, 3, [&](sim::CameraConfig& c) {
    c.exposure_changes.push_back({{t0 + 3'000'000'000, t0 + 4'000'000'000}, 0.4});
    c.darkness.push_back({t0 + 5'000'000'000, t0 + 6'000'000'000});
  });
  ASSERT_NE(camera, nullptr);
  ASSERT_EQ(camera->begin(), t0);
  std::vector<std::pair<Stamp, Image>> frames;
  for (Stamp t = t0 + 2'800'000'000; t <= t0 + 6'100'000'000; t += kFramePeriod)
    frames.emplace_back(t, camera->Render(t));
  const std::vector<Stamp> transitions = {t0 + 3'000'000'000, t0 + 4'000'000'000, t0 + 5'000'000'000,
                                          t0 + 6'000'000'000};
  for (const bool normalize : {true, false}) {
    FeatureTrackerConfig config;
    config.normalize_exposure = normalize;
    auto tracker = FeatureTracker::Create(camera->model(), config);
    ASSERT_TRUE(tracker);
    for (const auto& [t, image] : frames) {
      auto frame = tracker->Track(t, image);
      ASSERT_TRUE(frame);
      if (std::find(transitions.begin(), transitions.end(), t) == transitions.end()) continue;
      if (normalize)
        EXPECT_GT(frame->stats.tracked_ratio, 0.4) << ToSeconds(t - t0) << " s";
      else
        EXPECT_LT(frame->stats.tracked_ratio, 0.1) << ToSeconds(t - t0) << " s";
    }
  }
}

TEST(FeatureTracker, FramesOutOfOrderOrOfTheWrongSizeAreRefusedAndChangeNothing) {
  const auto camera = test::SimulatedCamera::Create("urban", 6.0, 2);
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker);
  const Stamp t0 = camera->begin() + 1'000'000'000;
  auto first = tracker->Track(t0, camera->Render(t0));
  ASSERT_TRUE(first);

  auto repeated = tracker->Track(t0, camera->Render(t0));
  ASSERT_FALSE(repeated);
  EXPECT_NE(repeated.error().find("not after the previous frame"), std::string::npos) << repeated.error();
  EXPECT_FALSE(tracker->Track(t0 - kFramePeriod, camera->Render(t0 - kFramePeriod)));
  auto small = tracker->Track(t0 + kFramePeriod, Filled(320, 240, 100));
  ASSERT_FALSE(small);
  EXPECT_NE(small.error().find("320 x 240 x 1 pixels, the camera is 640 x 480"), std::string::npos)
      << small.error();

  const Stamp t1 = t0 + kFramePeriod;
  auto next = tracker->Track(t1, camera->Render(t1));
  ASSERT_TRUE(next) << next.error();
  EXPECT_GT(next->stats.tracked_ratio, 0.7);  // tracked from the first frame, as if nothing had come between
}

TEST(FeatureTracker, NoFeatureLiesUnderTheMask) {
  const auto camera = test::SimulatedCamera::Create("urban", 6.0, 1);
  ASSERT_NE(camera, nullptr);
  const int w = camera->model().width(), h = camera->model().height();
  Image mask = Filled(w, h, 255);
  for (int y = 0; y < h; ++y)
    std::fill_n(mask.pixels.begin() + static_cast<std::ptrdiff_t>(y) * w, w / 2, 0);  // left half: ego
  auto tracker = FeatureTracker::Create(camera->model(), {}, mask);
  ASSERT_TRUE(tracker) << tracker.error();
  int features = 0;
  for (int k = 0; k < 5; ++k) {
    const Stamp t = camera->begin() + 1'000'000'000 + k * kFramePeriod;
    auto frame = tracker->Track(t, camera->Render(t));
    ASSERT_TRUE(frame);
    for (const TrackedFeature& f : frame->features) EXPECT_GE(f.pixel.x(), w / 2 - 0.5);
    features += frame->stats.features;
  }
  EXPECT_GT(features, 5 * 40);

  const auto wrong = FeatureTracker::Create(camera->model(), {}, Filled(w, h - 1, 255));
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().find("640 x 479 with 1 channels, the camera is 640 x 480"), std::string::npos)
      << wrong.error();
}

TEST(FeatureTracker, ConfigErrorsNameTheField) {
  const PinholeRadtan camera(
      {.pinhole = {.width = 64, .height = 48, .fx = 50, .fy = 50, .cx = 32, .cy = 24}});
  FeatureTrackerConfig config;
  config.max_features = 0;
  EXPECT_EQ(FeatureTracker::Create(camera, config).error(), "max_features: must be at least 1, got 0");
  config = {};
  config.klt_window_px = 20;
  EXPECT_EQ(FeatureTracker::Create(camera, config).error(),
            "klt_window_px: must be odd and at least 5, got 20");
  config = {};
  config.ransac_confidence = 1;
  EXPECT_EQ(FeatureTracker::Create(camera, config).error(), "ransac_confidence: must be in (0, 1), got 1");
  config = {};
  config.smoothing_sigma_px = std::nan("");
  EXPECT_EQ(FeatureTracker::Create(camera, config).error(), "smoothing_sigma_px: must be in [0, 5], got nan");
  config.smoothing_sigma_px = 6;
  EXPECT_EQ(FeatureTracker::Create(camera, config).error(), "smoothing_sigma_px: must be in [0, 5], got 6");
  const PinholeRadtan no_focal(
      {.pinhole = {.width = 64, .height = 48, .fx = 0, .fy = 50, .cx = 32, .cy = 24}});
  EXPECT_NE(FeatureTracker::Create(no_focal, {}).error().find("fx"), std::string::npos);
}

}  // namespace
}  // namespace uf::estimator
