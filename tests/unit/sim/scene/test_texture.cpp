// SurfaceColor: a deterministic procedural texture in [0, 1] with detail for every material.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/sim/scene/scene.h"

namespace uf::sim {
namespace {

// Colours on a 1 m x 1 m patch of a wall (normal +y, texture plane x-z) sampled every 2 cm.
std::vector<Eigen::Vector3f> Patch(Material m, const Eigen::Vector3d& origin, const Eigen::Vector3f& n) {
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < 50; ++i) {
    for (int j = 0; j < 50; ++j) {
      const Eigen::Vector3d p = n.z() > 0.5 ? origin + Eigen::Vector3d(0.02 * i, 0.02 * j, 0)
                                            : origin + Eigen::Vector3d(0.02 * i, 0, 0.02 * j);
      out.push_back(SurfaceColor(m, p, n));
    }
  }
  return out;
}

double LuminanceStd(const std::vector<Eigen::Vector3f>& colours) {
  double sum = 0.0, sum2 = 0.0;
  for (const auto& c : colours) {
    const double y = c.mean();
    sum += y;
    sum2 += y * y;
  }
  const double mean = sum / colours.size();
  return std::sqrt(std::max(0.0, sum2 / colours.size() - mean * mean));
}

TEST(SurfaceColor, DeterministicAndInUnitRange) {
  for (int m = 0; m < static_cast<int>(Material::kCount); ++m) {
    const auto material = static_cast<Material>(m);
    for (const auto& c : Patch(material, {-1234.5, 77.0, 3.0}, {0, 1, 0})) {
      EXPECT_TRUE((c.array() >= 0.0f).all() && (c.array() <= 1.0f).all()) << AppearanceOf(material).name;
    }
    const Eigen::Vector3d p(12.34, -5.67, 1.89);
    EXPECT_EQ(SurfaceColor(material, p, {0, 0, 1}), SurfaceColor(material, p, {0, 0, 1}));
  }
}

TEST(SurfaceColor, EveryMaterialIsTexturedOnWallsAndFloors) {
  for (int m = 0; m < static_cast<int>(Material::kCount); ++m) {
    const auto material = static_cast<Material>(m);
    // Several patches: a texture may have a uniform 1 m region somewhere, not everywhere.
    double best_wall = 0.0, best_floor = 0.0;
    for (int k = 0; k < 3; ++k) {
      best_wall = std::max(best_wall, LuminanceStd(Patch(material, {3.1 * k, 2.0, 0.5}, {0, 1, 0})));
      best_floor = std::max(best_floor, LuminanceStd(Patch(material, {3.1 * k, -7.0, 0.0}, {0, 0, 1})));
    }
    EXPECT_GT(best_wall, 0.01) << AppearanceOf(material).name;
    EXPECT_GT(best_floor, 0.01) << AppearanceOf(material).name;
  }
}

TEST(SurfaceColor, MaterialsDiffer) {
  for (int a = 0; a < static_cast<int>(Material::kCount); ++a) {
    const auto pa = Patch(static_cast<Material>(a), {0.3, 0.0, 0.2}, {0, 1, 0});
    for (int b = a + 1; b < static_cast<int>(Material::kCount); ++b) {
      const auto pb = Patch(static_cast<Material>(b), {0.3, 0.0, 0.2}, {0, 1, 0});
      double diff = 0.0;
      for (std::size_t i = 0; i < pa.size(); ++i) diff += (pa[i] - pb[i]).norm();
      EXPECT_GT(diff / pa.size(), 0.02) << AppearanceOf(static_cast<Material>(a)).name << " vs "
                                        << AppearanceOf(static_cast<Material>(b)).name;
    }
  }
}

TEST(SurfaceColor, BrickHasMortarCourses) {
  // Mortar (light grey) lines every 7.5 cm in z on a wall: along a vertical line, the fraction of mortar
  // samples is about the mortar thickness 1 cm / 7.5 cm.
  int mortar = 0, n = 0;
  for (double z = 0.0; z < 3.0; z += 0.001, ++n) {
    const Eigen::Vector3f c = SurfaceColor(Material::kBrick, {0.5, 1.0, z}, {0, -1, 0});
    if (std::abs(c.x() - c.z()) < 0.1f) ++mortar;  // grey, not red
  }
  EXPECT_NEAR(static_cast<double>(mortar) / n, 0.01 / 0.075, 0.05);
}

}  // namespace
}  // namespace uf::sim
