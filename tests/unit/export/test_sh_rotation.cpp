// SH rotation: a rotated Gaussian must show in direction R d the colour it showed in d, at directions other
// than the collocation ones (which also fails if a basis constant or sign broke rotation invariance), and
// degree 1 against the hand-derived permutation for the z-up -> y-up change of axes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "export/sh_rotation.h"

namespace uf::exporting {
namespace {

double Colour(const std::vector<float>& sh, int channel, int degree, const Eigen::Vector3d& d) {
  const std::array<double, 16> basis = ShBasis(d);
  double sum = 0;
  for (int k = 0; k < (degree + 1) * (degree + 1); ++k) sum += sh[3 * k + channel] * basis[k];
  return sum;
}

TEST(ShRotation, RotatedColourFunctionMatchesEverywhere) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    for (int degree = 0; degree <= 3; ++degree) {
      std::vector<float> sh(3 * (degree + 1) * (degree + 1));
      for (float& c : sh) c = static_cast<float>(g(rng));
      std::vector<float> rotated = sh;
      ShRotation(R).Apply(rotated.data(), degree);
      for (int s = 0; s < 50; ++s) {
        const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
        for (int c = 0; c < 3; ++c)  // float coefficients: ~1e-6 relative
          ASSERT_NEAR(Colour(rotated, c, degree, R * d), Colour(sh, c, degree, d), 2e-5)
              << "degree " << degree << " trial " << trial;
      }
    }
  }
}

TEST(ShRotation, IdentityKeepsCoefficients) {
  std::vector<float> sh(48);
  for (int i = 0; i < 48; ++i) sh[i] = 0.1f * i - 2.0f;
  std::vector<float> same = sh;
  ShRotation(Eigen::Matrix3d::Identity()).Apply(same.data(), 3);
  for (int i = 0; i < 48; ++i) EXPECT_NEAR(same[i], sh[i], 1e-6) << i;
}

// (x, y, z)' = (x, z, -y). Degree 1 is (-C y, C z, -C x) with coefficients (a, b, c): the colour
// -C a y + C b z - C c x at d = (x', -z', y') is C a z' + C b y' - C c x', i.e. coefficients (-b, a, c).
TEST(ShRotation, DegreeOneForTheGltfAxesIsTheHandDerivedPermutation) {
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  std::vector<float> sh(12, 0.0f);
  const float a = 0.3f, b = -0.7f, c = 1.1f;
  sh[3] = a;  // channel R only
  sh[6] = b;
  sh[9] = c;
  ShRotation(R).Apply(sh.data(), 1);
  EXPECT_NEAR(sh[3], -b, 1e-7);
  EXPECT_NEAR(sh[6], a, 1e-7);
  EXPECT_NEAR(sh[9], c, 1e-7);
  EXPECT_NEAR(sh[4], 0.0f, 1e-7);  // other channels untouched
}

}  // namespace
}  // namespace uf::exporting
