// Seeds from triangulated corners (viewer/pipeline/splat/feature_seeds.h) against a scene of known geometry:
// a wall of random grey blocks 8 m in front of a camera that slides sideways, ray-cast with 4 x 4 samples
// per pixel. The seeds must lie on the wall, keep clear of the map seeds, and be sized by their depth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "viewer/pipeline/splat/feature_seeds.h"

namespace uf::pipeline {
namespace {

constexpr double kWallZ = 8.0, kBlock = 0.5;  // m
constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 120.0;

// The wall's grey at (x, y): one random level per block.
double WallGrey(double x, double y) {
  const auto i = static_cast<std::int64_t>(std::floor(x / kBlock)),
             j = static_cast<std::int64_t>(std::floor(y / kBlock));
  const std::uint64_t hash =
      (static_cast<std::uint64_t>(i) * 73856093u) ^ (static_cast<std::uint64_t>(j) * 19349663u);
  return 30 + static_cast<double>((hash * 2654435761u >> 8) % 196);
}

// The camera at (x, 0, 0) looking along +z (OpenCV axes, the world's), seeing the wall at z = kWallZ.
StoredView WallView(double x, Stamp stamp) {
  StoredView view;
  view.stamp = stamp;
  view.camera.pinhole = {kWidth, kHeight, kFocal, kFocal, (kWidth - 1) / 2.0, (kHeight - 1) / 2.0};
  view.camera.T_world_camera = SE3(SO3(), Eigen::Vector3d(x, 0, 0));
  view.rgb.resize(3 * kWidth * kHeight);
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      double sum = 0;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double pu = u - 0.375 + 0.25 * a, pv = v - 0.375 + 0.25 * b;
          sum += WallGrey(x + kWallZ * (pu - view.camera.pinhole.cx) / kFocal,
                          kWallZ * (pv - view.camera.pinhole.cy) / kFocal);
        }
      for (int c = 0; c < 3; ++c)
        view.rgb[3 * (v * kWidth + u) + c] = static_cast<std::uint8_t>(std::lround(sum / 16));
    }
  return view;
}

std::vector<StoredView> SlidingViews(int count, double step_m) {
  std::vector<StoredView> views;
  for (int k = 0; k < count; ++k) views.push_back(WallView(k * step_m, 1'000'000'000LL * (k + 1)));
  return views;
}

TEST(FeatureSeeds, CornersTriangulateOntoTheWallAndKeepClearOfTheMap) {
  // Map seeds cover the wall left of x = -1 m on a 0.2 m grid.
  splat::GaussianModel model;
  model.sh_degree = 0;
  for (double x = -6; x <= -1; x += 0.2)
    for (double y = -4; y <= 4; y += 0.2)
      model.AddConstantColor(Eigen::Vector3f(x, y, kWallZ), Eigen::Vector3f::Constant(-2),
                             Eigen::Quaternionf::Identity(), 0, Eigen::Vector3f::Constant(0.5f));
  const std::size_t map_seeds = model.size();
  const FeatureSeedOptions options;
  Expected<FeatureSeedStats> stats = AddFeatureSeeds(model, map_seeds, SlidingViews(5, 0.4), options);
  ASSERT_TRUE(stats.ok()) << stats.error();
  EXPECT_GT(stats->tracks, 50u);
  EXPECT_GT(stats->near_map, 5u);
  EXPECT_GT(stats->added, 30u);
  EXPECT_EQ(stats->triangulated, stats->near_map + stats->added);
  ASSERT_EQ(model.size(), map_seeds + stats->added);
  ASSERT_TRUE(model.Validate().ok());
  // On the wall: 1 px over baselines of 0.4-1.6 m at 8 m is 0.04-0.13 m of depth. A rare track that slips
  // onto a neighbouring block with a consistent parallax (2 of 210 here, 0.5 m off) is left to the optimizer.
  std::size_t on_wall = 0;
  for (std::size_t i = map_seeds; i < model.size(); ++i) {
    const Eigen::Vector3f& p = model.positions[i];
    if (std::abs(p.z() - kWallZ) > 0.15) continue;
    ++on_wall;
    EXPECT_GT(p.x(), -1 + options.map_clearance_m - 0.2) << p.transpose();
    // Round, sized by the nearest camera's depth: min_distance_px at 8 m.
    const double scale = std::exp(model.log_scales[i].x());
    EXPECT_NEAR(scale, kWallZ * options.min_distance_px / kFocal, 0.03);
    EXPECT_EQ(model.log_scales[i].x(), model.log_scales[i].z());
  }
  EXPECT_GE(on_wall, 0.97 * stats->added);
}

TEST(FeatureSeeds, OneViewOrNoParallaxAddsNothing) {
  splat::GaussianModel model;
  model.sh_degree = 0;
  Expected<FeatureSeedStats> stats = AddFeatureSeeds(model, 0, SlidingViews(1, 0.4));
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(model.size(), 0u);
  // A camera that stays put: every track has parallel rays.
  stats = AddFeatureSeeds(model, 0, SlidingViews(4, 0.0));
  ASSERT_TRUE(stats.ok()) << stats.error();
  EXPECT_GT(stats->tracks, 50u);
  EXPECT_EQ(stats->triangulated, 0u);
  EXPECT_EQ(model.size(), 0u);
}

}  // namespace
}  // namespace uf::pipeline
