// The sky sphere and the scene extent against hand-computed values: the radius from the 95th percentile of
// the seeded Gaussians' distances, its reduction for the size-pruning limit, the count and the opacity; the
// scene extent as the largest camera distance from the centroid.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "splat/sky.h"
#include "splat/training/scene_extent.h"

namespace uf::splat {
namespace {

// Two cameras 2 m apart: centre (1, 0, 0), scene extent 1 m.
const std::vector<Eigen::Vector3d> kCameras = {{0, 0, 0}, {2, 0, 0}};

// 21 seeded Gaussians at 5, 10, ..., 105 m from (1, 0, 0), in a shuffled order.
GaussianModel Seeded() {
  GaussianModel model;
  model.sh_degree = 0;
  for (int k : {7, 20, 0, 13, 3, 18, 9, 1, 15, 11, 5, 19, 2, 16, 8, 12, 4, 17, 6, 14, 10})
    model.AddConstantColor(Eigen::Vector3f(1, 0, 5.0f * (k + 1)), Eigen::Vector3f::Zero(),
                           Eigen::Quaternionf::Identity(), 0, Eigen::Vector3f::Constant(0.5f));
  return model;
}

double Opacity(float logit) { return 1 / (1 + std::exp(-static_cast<double>(logit))); }

TEST(SceneExtent, IsTheLargestCameraDistanceFromTheCentroid) {
  // Centroid (1, 1, 0): distances sqrt(2), sqrt(2) and 2.
  const std::vector<Eigen::Vector3d> cameras = {{0, 0, 0}, {2, 0, 0}, {1, 3, 0}};
  EXPECT_DOUBLE_EQ(SceneExtent(cameras), 2.0);
  EXPECT_DOUBLE_EQ(SceneExtent(kCameras), 1.0);
  // At least 1 mm: one camera, or none.
  EXPECT_DOUBLE_EQ(SceneExtent(std::vector<Eigen::Vector3d>{{4, 5, 6}}), 1e-3);
  EXPECT_DOUBLE_EQ(SceneExtent({}), 1e-3);
}

TEST(Sky, RadiusIs1Point2TimesThe95thPercentileDistance) {
  GaussianModel model = Seeded();
  // The element of rank floor(0.95 x 20) = 19 among the sorted distances: 100 m, so r = 120 m. The pruning
  // limit allows up to 100 x 1 m x sqrt(200 / 4 pi) = 399 m.
  const std::optional<SkySphere> sky = AddSky(model, kCameras, 200, 100.0);
  ASSERT_TRUE(sky.has_value());
  EXPECT_EQ(sky->centre, Eigen::Vector3d(1, 0, 0));
  EXPECT_NEAR(sky->radius, 120.0, 1e-9);
  ASSERT_EQ(model.size(), 21u + 200u);
  for (std::size_t i = 21; i < model.size(); ++i) {
    EXPECT_NEAR((model.positions[i].cast<double>() - sky->centre).norm(), 120.0, 1e-4);
    EXPECT_NEAR(Opacity(model.opacity_logits[i]), 0.5, 1e-7);
  }
  // The seeded Gaussians are kept as they were.
  EXPECT_EQ(model.positions[0], Eigen::Vector3f(1, 0, 40));
}

TEST(Sky, IsAtLeastTenMetresAway) {
  GaussianModel empty;
  empty.sh_degree = 0;
  const std::optional<SkySphere> sky = AddSky(empty, kCameras, 50, 100.0);
  ASSERT_TRUE(sky.has_value());
  EXPECT_DOUBLE_EQ(sky->radius, 10.0);
  EXPECT_EQ(empty.size(), 50u);
}

TEST(Sky, ShrinksSoThatItsDiscsSurviveThePruning) {
  GaussianModel model = Seeded();
  // prune_world_fraction 0.1 x extent 1 m: the spacing r sqrt(4 pi / n) may be at most 0.1 m, so
  // r = 0.1 sqrt(400 / 4 pi) = 0.5642 m, and each disc's tangent scale is half the spacing, 0.05 m.
  const std::optional<SkySphere> sky = AddSky(model, kCameras, 400, 0.1);
  ASSERT_TRUE(sky.has_value());
  EXPECT_NEAR(sky->radius, 0.1 * std::sqrt(400 / (4 * M_PI)), 1e-12);
  EXPECT_NEAR(sky->radius, 0.5642, 1e-4);
  ASSERT_EQ(model.size(), 21u + 400u);
  for (std::size_t i = 21; i < model.size(); ++i) EXPECT_NEAR(std::exp(model.log_scales[i].x()), 0.05, 1e-6);
}

TEST(Sky, NothingWithoutCamerasOrGaussians) {
  GaussianModel model = Seeded();
  EXPECT_FALSE(AddSky(model, {}, 100, 0.1).has_value());
  EXPECT_FALSE(AddSky(model, kCameras, 0, 0.1).has_value());
  EXPECT_EQ(model.size(), 21u);
}

}  // namespace
}  // namespace uf::splat
