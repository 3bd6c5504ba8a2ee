// `eval --align yaw` (AlignMode::kYaw) against hand-computed cases: an estimate that differs from the
// reference by a rotation about z and a translation aligns exactly; one whose world is also tilted keeps the
// tilt as error (r sin(theta) / sqrt(2) for a circle of radius r tilted by theta about a diameter), where the
// SE3 alignment removes it; an estimate that does not move horizontally is refused.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/eval/evaluation.h"

namespace uf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A circle of radius r about the origin in the level plane, one pose per degree, 10 ms apart.
Trajectory Circle(double r) {
  Trajectory t;
  for (int k = 0; k < 360; ++k) {
    const double phi = 2 * kPi * k / 360;
    t.stamps.push_back(1'000'000'000 + 10'000'000LL * k);
    t.poses.emplace_back(SO3::Exp(Eigen::Vector3d(0, 0, phi)),
                         Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), 0));
  }
  return t;
}

Trajectory Moved(const Trajectory& t, const SE3& T) {
  Trajectory moved = t;
  for (SE3& pose : moved.poses) pose = T * pose;
  return moved;
}

double ApeRmse(const Trajectory& reference, const Trajectory& estimate, AlignMode align) {
  EvalOptions options;
  options.align = align;
  const Expected<EvalResult> result = Evaluate(reference, estimate, options);
  EXPECT_TRUE(result.ok()) << result.error();
  return result ? result->ape.rmse : -1;
}

TEST(YawAlignment, RemovesAYawAndATranslationButNotATilt) {
  const double r = 10, tilt = 1 * kPi / 180;
  const Trajectory reference = Circle(r);
  const SE3 yawed(SO3::Exp(Eigen::Vector3d(0, 0, 0.5)), Eigen::Vector3d(3, -2, 1));
  EXPECT_LT(ApeRmse(reference, Moved(reference, yawed), AlignMode::kYaw), 1e-9);
  // Tilted about the x axis through the circle's centre: z = r sin(theta) sin(phi), RMS r sin(theta) / sqrt
  // 2; the horizontal change is second order (r (1 - cos theta) ~ 1.5 mm).
  const Trajectory tilted =
      Moved(reference, yawed * SE3(SO3::Exp(Eigen::Vector3d(tilt, 0, 0)), Eigen::Vector3d::Zero()));
  EXPECT_NEAR(ApeRmse(reference, tilted, AlignMode::kYaw), r * std::sin(tilt) / std::sqrt(2.0), 1e-3);
  EXPECT_LT(ApeRmse(reference, tilted, AlignMode::kSe3), 1e-9);
}

TEST(YawAlignment, RefusesAnEstimateThatDoesNotMoveHorizontally) {
  Trajectory reference = Circle(5), still = reference;
  for (std::size_t k = 0; k < still.size(); ++k) still.poses[k] = SE3(SO3(), Eigen::Vector3d(1, 2, 0.01 * k));
  EvalOptions options;
  options.align = AlignMode::kYaw;
  const Expected<EvalResult> result = Evaluate(reference, still, options);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("does not move horizontally"), std::string::npos) << result.error();
}

}  // namespace
}  // namespace uf
