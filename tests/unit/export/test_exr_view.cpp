// EXR views: the sRGB EOTF against hand-computed values, float and half round trips (channels, types,
// pixel order, inf depth), and errors that leave no file behind.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "export/exr_view.h"
#include "export_test_util.h"

namespace uf::exporting {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A width x height view with distinct values everywhere; every 7th pixel is background (inf depths).
splat::RenderedView MakeView(int width, int height, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  splat::RenderedView view;
  view.width = width;
  view.height = height;
  const int n = width * height;
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) view.rgb.push_back(u(rng));
    view.alpha.push_back(i % 7 == 0 ? 0.0f : u(rng));
    view.depth.push_back(i % 7 == 0 ? kInf : 1.0f + 50.0f * u(rng));
    view.expected_depth.push_back(i % 7 == 0 ? kInf : 1.0f + 50.0f * u(rng));
  }
  return view;
}

TEST(ExrView, SrgbToLinearMatchesHandComputedValues) {
  // IEC 61966-2-1: v / 12.92 up to 0.04045, ((v + 0.055) / 1.055)^2.4 above.
  EXPECT_EQ(SrgbToLinear(0.0f), 0.0f);
  EXPECT_NEAR(SrgbToLinear(1.0f), 1.0f, 1e-7);
  EXPECT_NEAR(SrgbToLinear(0.02f), 0.02f / 12.92f, 1e-9);         // linear segment
  EXPECT_NEAR(SrgbToLinear(0.04045f), 0.0031308f, 1e-7);          // the joint, both pieces agree
  EXPECT_NEAR(SrgbToLinear(0.5f), 0.21404114f, 1e-7);             // (0.555 / 1.055)^2.4
  EXPECT_NEAR(SrgbToLinear(0.2f), 0.03310477f, 1e-8);             // (0.255 / 1.055)^2.4
  EXPECT_NEAR(SrgbToLinear(128.0f / 255.0f), 0.21586050f, 1e-7);  // mid grey byte
  EXPECT_NEAR(SrgbToLinear(1.2f), 1.5168374f, 1e-6);              // above 1: the power law goes on
}

TEST(ExrView, FloatRoundTripKeepsEveryChannelExactly) {
  test::ScratchDir dir;
  const splat::RenderedView view = MakeView(37, 23, 1);
  const std::string path = (dir / "v.exr").string();
  ASSERT_TRUE(WriteViewExr(view, path, ExrPixelType::kFloat).ok());
  Expected<ExrImage> image = ReadExr(path);
  ASSERT_TRUE(image.ok()) << image.error();
  EXPECT_EQ(image->width, 37);
  EXPECT_EQ(image->height, 23);
  ASSERT_EQ(image->channels.size(), 6u);
  for (const char* name : {"R", "G", "B", "A", "Z", kExrExpectedDepthChannel})
    EXPECT_EQ(image->types.at(name), ExrPixelType::kFloat) << name;
  const char* rgb[3] = {"R", "G", "B"};
  for (int i = 0; i < 37 * 23; ++i) {
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(image->channels.at(rgb[c])[i], SrgbToLinear(view.rgb[3 * i + c])) << i;
    ASSERT_EQ(image->channels.at("A")[i], view.alpha[i]);
    ASSERT_EQ(image->channels.at("Z")[i], view.depth[i]);  // inf stays inf
    ASSERT_EQ(image->channels.at(kExrExpectedDepthChannel)[i], view.expected_depth[i]);
  }
  EXPECT_TRUE(std::isinf(image->channels.at("Z")[0]));
  EXPECT_EQ(dir.Entries().size(), 1u);
}

// Half RGBA: a half has an 11-bit significand, so rounding to nearest is within 2^-11 relative for normal
// values (>= 2^-14) and within 2^-25 absolute below (subnormal spacing 2^-24).
TEST(ExrView, HalfRoundTripWithinHalfPrecision) {
  test::ScratchDir dir;
  splat::RenderedView view = MakeView(16, 9, 2);
  view.rgb[0] = 0.0f;
  view.rgb[1] = 0.001f;  // linear 7.7e-5: near the bottom of the normal range
  view.rgb[2] = 1.0f;
  const std::string path = (dir / "h.exr").string();
  ASSERT_TRUE(WriteViewExr(view, path).ok());  // half is the default
  Expected<ExrImage> image = ReadExr(path);
  ASSERT_TRUE(image.ok()) << image.error();
  for (const char* name : {"R", "G", "B", "A"}) EXPECT_EQ(image->types.at(name), ExrPixelType::kHalf) << name;
  EXPECT_EQ(image->types.at("Z"), ExrPixelType::kFloat);
  EXPECT_EQ(image->types.at(kExrExpectedDepthChannel), ExrPixelType::kFloat);
  auto tolerance = [](float v) { return std::max(std::ldexp(std::abs(v), -11), std::ldexp(1.0f, -25)); };
  const char* rgb[3] = {"R", "G", "B"};
  for (int i = 0; i < 16 * 9; ++i) {
    for (int c = 0; c < 3; ++c) {
      const float linear = SrgbToLinear(view.rgb[3 * i + c]);
      ASSERT_NEAR(image->channels.at(rgb[c])[i], linear, tolerance(linear)) << i << " " << c;
    }
    ASSERT_NEAR(image->channels.at("A")[i], view.alpha[i], tolerance(view.alpha[i]));
    ASSERT_EQ(image->channels.at("Z")[i], view.depth[i]);  // depth stays float
  }
  EXPECT_EQ(image->channels.at("R")[0], 0.0f);
  EXPECT_EQ(image->channels.at("B")[0], 1.0f);
}

TEST(ExrView, PixelOrderIsRowMajorFromTheTopLeft) {
  test::ScratchDir dir;
  splat::RenderedView view = MakeView(3, 2, 3);
  for (int i = 0; i < 6; ++i) view.depth[i] = 10.0f * (i / 3) + (i % 3);  // 10 y + x
  ASSERT_TRUE(WriteViewExr(view, (dir / "o.exr").string(), ExrPixelType::kFloat).ok());
  Expected<ExrImage> image = ReadExr((dir / "o.exr").string());
  ASSERT_TRUE(image.ok()) << image.error();
  EXPECT_EQ(image->channels.at("Z"), (std::vector<float>{0, 1, 2, 10, 11, 12}));
}

TEST(ExrView, BadViewsAndFilesGiveErrors) {
  test::ScratchDir dir;
  const std::string path = (dir / "v.exr").string();
  ASSERT_TRUE(WriteViewExr(MakeView(4, 4, 4), path).ok());
  const std::vector<std::uint8_t> good = test::ReadBytes(path);
  splat::RenderedView short_alpha = MakeView(4, 4, 5);
  short_alpha.alpha.pop_back();
  const Status s = WriteViewExr(short_alpha, path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("v.exr"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("alpha 15"), std::string::npos) << s.message();
  EXPECT_EQ(test::ReadBytes(path), good);  // the good file is untouched
  splat::RenderedView empty;
  EXPECT_FALSE(WriteViewExr(empty, (dir / "e.exr").string()).ok());
  EXPECT_FALSE(WriteViewExr(MakeView(2, 2, 6), (dir / "no/dir/x.exr").string()).ok());
  EXPECT_EQ(dir.Entries().size(), 1u);

  std::ofstream(dir / "garbage.exr", std::ios::binary) << "not an exr file at all";
  Expected<ExrImage> garbage = ReadExr((dir / "garbage.exr").string());
  ASSERT_FALSE(garbage.ok());
  EXPECT_NE(garbage.error().find("garbage.exr"), std::string::npos) << garbage.error();
  std::ofstream(dir / "cut.exr", std::ios::binary)
      .write(reinterpret_cast<const char*>(good.data()), static_cast<std::streamsize>(good.size() / 2));
  EXPECT_FALSE(ReadExr((dir / "cut.exr").string()).ok());
  EXPECT_FALSE(ReadExr((dir / "missing.exr").string()).ok());
}

}  // namespace
}  // namespace uf::exporting
