// Exposure compensation (splat/training/exposure.h) against images made with a known gain and bias.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "splat/training/exposure.h"

namespace uf::splat {
namespace {

// A render of n pixels with values spread over [0.05, 0.95], and the image a camera with `truth` records of
// it, quantised to 8 bits and clipped to [0, 1].
struct Pair {
  std::vector<float> rendered, image;
};
Pair MakePair(const Exposure& truth, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<float> value(0.05f, 0.95f);
  Pair pair;
  for (std::size_t i = 0; i < 3 * n; ++i) {
    const float r = value(random);
    const float t = truth.gain[i % 3] * r + truth.bias[i % 3];
    pair.rendered.push_back(r);
    pair.image.push_back(std::round(255.0f * std::clamp(t, 0.0f, 1.0f)) / 255.0f);
  }
  return pair;
}

void ExpectNear(const Exposure& got, const Exposure& want, float tolerance) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(got.gain[c], want.gain[c], tolerance) << "channel " << c;
    EXPECT_NEAR(got.bias[c], want.bias[c], tolerance) << "channel " << c;
  }
}

TEST(Exposure, FitRecoversGainAndBiasDespiteClippedPixels) {
  // Channel 0 is brightened so far that a third of its pixels clip at 1: they follow no affine law.
  const Exposure truth{{1.5f, 0.8f, 1.1f}, {0.1f, 0.05f, -0.04f}};
  const Pair pair = MakePair(truth, 20000, 1);
  ExposureFitOptions options;
  options.prior_weight = 0;
  ExpectNear(FitExposure(pair.rendered, pair.image, options), truth, 2e-3f);
}

TEST(Exposure, HuberWeightsResistAMovingObject) {
  const Exposure truth{{0.7f, 0.75f, 0.8f}, {0.02f, 0.0f, 0.03f}};
  Pair pair = MakePair(truth, 20000, 2);
  // A fifth of the image shows something the render does not (a passing car): dark pixels.
  for (std::size_t i = 0; i < pair.image.size() / 5; ++i) pair.image[i] = 0.08f;
  ExposureFitOptions options;
  options.prior_weight = 0;
  options.reweightings = 0;
  const Exposure least_squares = FitExposure(pair.rendered, pair.image, options);
  options.reweightings = 5;
  const Exposure huber = FitExposure(pair.rendered, pair.image, options);
  EXPECT_GT(std::abs(least_squares.gain[0] - truth.gain[0]), 0.1f);  // plain least squares is pulled away
  ExpectNear(huber, truth, 0.02f);
}

TEST(Exposure, PriorPullsTowardsIdentity) {
  // t = 2 r clips above r = 0.5, so the fit sees r uniform on [0.05, 0.5]; with lambda = 0.1 the normal
  // equations of the header (per pixel: S_rr = 0.0925, S_r = 0.275) give g = 1.19, b = 0.20, between the
  // truth and the identity. Without the prior: the truth.
  const Exposure truth{{2.0f, 2.0f, 2.0f}, {0.0f, 0.0f, 0.0f}};
  const Pair pair = MakePair(truth, 20000, 3);
  ExposureFitOptions options;
  options.prior_weight = 0.1;
  options.reweightings = 0;
  const Exposure fitted = FitExposure(pair.rendered, pair.image, options);
  EXPECT_NEAR(fitted.gain[1], 1.19f, 0.03f);
  EXPECT_NEAR(fitted.bias[1], 0.20f, 0.02f);
  options.prior_weight = 0;
  EXPECT_NEAR(FitExposure(pair.rendered, pair.image, options).gain[1], 2.0f, 3e-3f);
  EXPECT_EQ(FitExposure(std::vector<float>(30, 0.5f), std::vector<float>(30, 1.0f)).gain[0], 1.0f)
      << "no usable pixel (all clipped): identity";
}

TEST(Exposure, ApplyAndRemoveAreInverse) {
  const Exposure e{{1.25f, 0.5f, 2.0f}, {0.1f, -0.2f, 0.0f}};
  std::vector<float> rgb = {0.2f, 0.4f, 0.6f, 0.0f, 1.0f, 0.5f};
  const std::vector<float> original = rgb;
  ApplyExposure(e, rgb);
  EXPECT_FLOAT_EQ(rgb[0], 1.25f * 0.2f + 0.1f);
  EXPECT_FLOAT_EQ(rgb[4], 0.5f * 1.0f - 0.2f);
  RemoveExposure(e, rgb);
  for (std::size_t i = 0; i < rgb.size(); ++i) EXPECT_NEAR(rgb[i], original[i], 1e-6f);
}

TEST(Exposure, InterpolatesInTimeAndHoldsAtTheEnds) {
  const std::vector<Stamp> stamps = {100, 200, 400};
  std::vector<Exposure> exposures(3);
  exposures[0].gain = {1.0f, 1.0f, 1.0f};
  exposures[1].gain = {2.0f, 1.0f, 1.0f};
  exposures[2].gain = {4.0f, 1.0f, 1.0f};
  exposures[2].bias = {0.2f, 0.0f, 0.0f};
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 150).gain[0], 1.5f);
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 350).gain[0], 3.5f);
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 350).bias[0], 0.15f);
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 200).gain[0], 2.0f);
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 50).gain[0], 1.0f);
  EXPECT_FLOAT_EQ(InterpolateExposure(stamps, exposures, 500).gain[0], 4.0f);
  EXPECT_FLOAT_EQ(InterpolateExposure({}, {}, 500).gain[0], 1.0f);
}

}  // namespace
}  // namespace uf::splat
