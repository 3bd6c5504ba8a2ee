// Umeyama alignment: recovers a known similarity exactly, agrees with Eigen's independent implementation on
// noisy data, refuses degenerate (collinear) input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "odometry/eval/alignment.h"

namespace uf {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int n, std::mt19937& random) {
  std::normal_distribution<double> normal(0, 3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(normal(random), normal(random), normal(random));
  return points;
}

TEST(Umeyama, RecoversAKnownSimilarity) {
  std::mt19937 random(7);
  const auto source = RandomPoints(50, random);
  const SO3 R = SO3::Exp(Eigen::Vector3d(0.3, -1.2, 2.0));
  const Eigen::Vector3d t(4, -5, 6);
  const double s = 2.5;
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) target.push_back(s * (R * p) + t);

  auto sim3 = Umeyama(source, target, true);
  ASSERT_TRUE(sim3) << sim3.error();
  EXPECT_NEAR(sim3->scale, s, 1e-12);
  EXPECT_LT((sim3->rotation.matrix() - R.matrix()).norm(), 1e-12);
  EXPECT_LT((sim3->translation - t).norm(), 1e-11);

  auto se3 = Umeyama(source, target, false);  // without scale the rotation is still found exactly
  ASSERT_TRUE(se3);
  EXPECT_EQ(se3->scale, 1.0);
  EXPECT_LT((se3->rotation.matrix() - R.matrix()).norm(), 1e-12);
}

TEST(Umeyama, AgreesWithEigenOnNoisyData) {
  std::mt19937 random(11);
  const auto source = RandomPoints(200, random);
  std::normal_distribution<double> noise(0, 0.2);
  const SO3 R = SO3::Exp(Eigen::Vector3d(2.9, 0.1, -0.4));  // close to a half turn
  Eigen::Matrix3Xd src(3, source.size()), dst(3, source.size());
  std::vector<Eigen::Vector3d> target;
  for (std::size_t i = 0; i < source.size(); ++i) {
    target.push_back(0.7 * (R * source[i]) + Eigen::Vector3d(1, 2, 3) +
                     Eigen::Vector3d(noise(random), noise(random), noise(random)));
    src.col(i) = source[i];
    dst.col(i) = target.back();
  }
  for (bool with_scale : {false, true}) {
    const Eigen::Matrix4d expected = Eigen::umeyama(src, dst, with_scale);
    auto ours = Umeyama(source, target, with_scale);
    ASSERT_TRUE(ours);
    EXPECT_LT((ours->rotation.matrix() * ours->scale - expected.topLeftCorner<3, 3>()).norm(), 1e-12);
    EXPECT_LT((ours->translation - expected.topRightCorner<3, 1>()).norm(), 1e-12);
  }
}

TEST(Umeyama, PlanarPointsAreFineCollinearOnesAreNot) {
  std::vector<Eigen::Vector3d> planar = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_TRUE(Umeyama(planar, planar, false));
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(0.1 * i, 0.2 * i, -0.3 * i);
  auto degenerate = Umeyama(line, line, true);
  ASSERT_FALSE(degenerate);
  EXPECT_NE(degenerate.error().find("collinear"), std::string::npos);
  auto few = Umeyama({planar[0], planar[1]}, {planar[0], planar[1]}, false);
  ASSERT_FALSE(few);
  EXPECT_NE(few.error().find("at least 3 matched pairs, got 2"), std::string::npos);
}

}  // namespace
}  // namespace uf
