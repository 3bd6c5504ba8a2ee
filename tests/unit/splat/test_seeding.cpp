// Seeding Gaussians from map points, against hand-built maps: a tilted plane sampled on a known grid.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/seeding.h"

namespace uf::splat {
namespace {

// Points on the plane through `origin` spanned by unit vectors a, b, on an n x n grid of `spacing`.
std::vector<mapping::MapPoint> PlaneGrid(const Eigen::Vector3d& origin, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, int n, double spacing, bool coloured) {
  std::vector<mapping::MapPoint> points;
  const Eigen::Vector3f normal = a.cross(b).normalized().cast<float>();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      mapping::MapPoint p;
      p.position = origin + spacing * (i * a + j * b);
      p.normal = normal;
      p.has_color = coloured;
      p.rgb = {static_cast<std::uint8_t>(10 * i), 128, 255};
      points.push_back(p);
    }
  return points;
}

TEST(SeedGaussians, DiscsLieInTheSurfaceWithTheGridSpacingAsScale) {
  const Eigen::Vector3d a = Eigen::Vector3d(1, 1, 0).normalized(), b = Eigen::Vector3d(0, 0.6, 0.8);
  const double spacing = 0.05;
  const mapping::VectorPointSource map(PlaneGrid(Eigen::Vector3d(100, -20, 3), a, b, 20, spacing, true));
  Expected<SeedResult> seeded = SeedGaussians(map, SeedOptions{});
  ASSERT_TRUE(seeded.ok()) << seeded.error();
  const GaussianModel& model = seeded->model;
  ASSERT_EQ(model.size(), 400u);
  EXPECT_EQ(model.sh_degree, 3);
  EXPECT_TRUE(model.Validate().ok());
  EXPECT_EQ(seeded->uncoloured, 0u);
  const Eigen::Vector3f normal = a.cross(b).normalized().cast<float>();
  // An interior point: its 3 nearest neighbours are 4 grid neighbours at `spacing`, so s = spacing.
  const std::size_t interior = 10 * 20 + 10;
  const Eigen::Vector3f scale = model.log_scales[interior].array().exp();
  EXPECT_NEAR(scale.x(), spacing, 1e-6);
  EXPECT_NEAR(scale.y(), spacing, 1e-6);
  EXPECT_NEAR(scale.z(), 0.1 * spacing, 1e-7);
  // The flat axis (local z) is the surface normal.
  const Eigen::Vector3f local_z = model.rotations[interior].normalized() * Eigen::Vector3f::UnitZ();
  EXPECT_NEAR(std::abs(local_z.dot(normal)), 1.0f, 1e-6f);
  // Colour: Y_0 f_dc + 0.5 gives back the point's colour (i = 10: red 100).
  const float* dc = model.sh.data() + interior * model.ShStride();
  EXPECT_NEAR(kShC0 * dc[0] + 0.5f, 100 / 255.0f, 1e-6f);
  EXPECT_NEAR(kShC0 * dc[2] + 0.5f, 1.0f, 1e-6f);
  EXPECT_NEAR(
      (model.positions[interior].cast<double>() - (Eigen::Vector3d(100, -20, 3) + 0.5 * (a + b))).norm(), 0,
      1e-5);
}

TEST(SeedGaussians, UncolouredPointsAreGreyAndCountedIsolatedOnesGetTheDefaultScale) {
  std::vector<mapping::MapPoint> points =
      PlaneGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 4, 0.1, false);
  mapping::MapPoint lonely;
  lonely.position = Eigen::Vector3d(50, 50, 50);  // no normal, no neighbour
  points.push_back(lonely);
  SeedOptions options;
  options.sh_degree = 0;
  Expected<SeedResult> seeded = SeedGaussians(mapping::VectorPointSource(points), options);
  ASSERT_TRUE(seeded.ok());
  EXPECT_EQ(seeded->uncoloured, 17u);
  EXPECT_EQ(seeded->isolated, 1u);
  EXPECT_EQ(seeded->without_normal, 1u);
  const GaussianModel& model = seeded->model;
  EXPECT_NEAR(kShC0 * model.sh[0] + 0.5f, 0.5f, 1e-7f);
  EXPECT_TRUE((model.log_scales[16].array().exp() - 0.25f).abs().maxCoeff() < 1e-6f);
  // Opacity 0.5 is logit 0.
  EXPECT_NEAR(model.opacity_logits[0], 0.0f, 1e-7f);
}

TEST(SeedGaussians, PointsNoCameraSawAreLeftOutOfAColouredMapAndTheBudgetGoesToTheSeenOnes) {
  // 100 coloured points on z = 0 and 100 uncoloured ones on z = 5 (behind the camera, say).
  std::vector<mapping::MapPoint> points =
      PlaneGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 10, 0.1, true);
  for (const mapping::MapPoint& p : PlaneGrid(Eigen::Vector3d(0, 0, 5), Eigen::Vector3d::UnitX(),
                                              Eigen::Vector3d::UnitY(), 10, 0.1, false))
    points.push_back(p);
  SeedOptions options;
  options.max_gaussians = 50;
  Expected<SeedResult> seeded = SeedGaussians(mapping::VectorPointSource(points), options);
  ASSERT_TRUE(seeded.ok());
  EXPECT_EQ(seeded->map_points, 200u);
  EXPECT_EQ(seeded->unseen_left_out, 100u);
  EXPECT_EQ(seeded->uncoloured, 0u);
  EXPECT_EQ(seeded->thinning, 2u);  // ceil(100 coloured / 50)
  ASSERT_EQ(seeded->model.size(), 50u);
  for (const Eigen::Vector3f& p : seeded->model.positions) EXPECT_EQ(p.z(), 0.0f);
  // Asked to keep them, every point counts again: 200 points thinned by 4, half of them grey.
  options.seen_points_only = false;
  seeded = SeedGaussians(mapping::VectorPointSource(points), options);
  ASSERT_TRUE(seeded.ok());
  EXPECT_EQ(seeded->unseen_left_out, 0u);
  EXPECT_EQ(seeded->thinning, 4u);
  EXPECT_EQ(seeded->model.size(), 50u);
  EXPECT_EQ(seeded->uncoloured, 25u);
}

TEST(SeedGaussians, ThinsToTheBudgetAndRejectsBadOptions) {
  const mapping::VectorPointSource map(
      PlaneGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 10, 0.1, true));
  SeedOptions options;
  options.max_gaussians = 30;
  Expected<SeedResult> seeded = SeedGaussians(map, options);
  ASSERT_TRUE(seeded.ok());
  EXPECT_EQ(seeded->thinning, 4u);  // ceil(100 / 30)
  EXPECT_EQ(seeded->model.size(), 25u);
  options = SeedOptions{};
  options.initial_opacity = 1.0;
  EXPECT_NE(SeedGaussians(map, options).error().find("seed.initial_opacity"), std::string::npos);
}

}  // namespace
}  // namespace uf::splat

namespace uf::splat {
namespace {

TEST(AddBackgroundSphere, EvenlySpacedDiscsOnTheSphereFacingTheCentre) {
  GaussianModel model;
  model.sh_degree = 1;
  const Eigen::Vector3d centre(10, -5, 2);
  const double radius = 50;
  const int count = 2000;
  AddBackgroundSphere(model, centre, radius, count, 0.1);
  ASSERT_EQ(model.size(), static_cast<std::size_t>(count));
  ASSERT_TRUE(model.Validate().ok());
  const double spacing = radius * std::sqrt(4 * M_PI / count);  // 3.96 m
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Eigen::Vector3d offset = model.positions[i].cast<double>() - centre;
    EXPECT_NEAR(offset.norm(), radius, 1e-4);
    mean += offset / count;
    // Local z (the disc's normal) along the radius.
    const Eigen::Vector3f normal = model.rotations[i].normalized() * Eigen::Vector3f::UnitZ();
    EXPECT_GT(std::abs(normal.dot(offset.normalized().cast<float>())), 0.9999f);
    EXPECT_NEAR(std::exp(model.log_scales[i].x()), spacing / 2, 1e-3);
    EXPECT_NEAR(1 / (1 + std::exp(-model.opacity_logits[i])), 0.1, 1e-6);
    EXPECT_NEAR(kShC0 * model.sh[i * model.ShStride()] + 0.5f, 0.5f, 1e-6f);
  }
  EXPECT_LT(mean.norm(), 0.01 * radius);  // spread over the whole sphere
  // Even spacing: every point's nearest neighbour lies within [0.5, 1.5] x the nominal spacing.
  for (std::size_t i = 0; i < model.size(); i += 97) {
    double nearest = 1e9;
    for (std::size_t j = 0; j < model.size(); ++j)
      if (j != i) nearest = std::min(nearest, double((model.positions[i] - model.positions[j]).norm()));
    EXPECT_GT(nearest, 0.5 * spacing) << i;
    EXPECT_LT(nearest, 1.5 * spacing) << i;
  }
}

}  // namespace
}  // namespace uf::splat
