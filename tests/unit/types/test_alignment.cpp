// Umeyama alignment: recovers a known similarity exactly, agrees with Eigen's independent implementation on
// noisy data, refuses degenerate (collinear) input. The weighted rigid alignment: recovers a known transform
// whatever the weights, in 3D and yaw-only, and a point's weight decides how much it pulls.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "odometry/types/alignment.h"

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

// A rigid transform with roll, pitch and yaw applied to random points: found exactly whatever the weights.
TEST(WeightedRigidAlignment, RecoversAKnownTransformWhateverTheWeights) {
  std::mt19937 random(7);
  const std::vector<Eigen::Vector3d> source = RandomPoints(30, random);
  const SE3 truth(SO3::Exp(Eigen::Vector3d(0.2, -0.1, 1.3)), Eigen::Vector3d(5, -2, 0.5));
  std::vector<Eigen::Vector3d> target;
  std::vector<double> weights;
  std::uniform_real_distribution<double> weight(0.01, 100);
  for (const Eigen::Vector3d& p : source) {
    target.push_back(truth * p);
    weights.push_back(weight(random));
  }
  const SE3 found = WeightedRigidAlignment(source, target, weights, false);
  EXPECT_LT((found.matrix() - truth.matrix()).norm(), 1e-12);
}

// Yaw-only: a transform about z alone is found exactly; with roll in the data the rotation stays about z.
TEST(WeightedRigidAlignment, YawOnlyKeepsTheZAxis) {
  std::mt19937 random(8);
  const std::vector<Eigen::Vector3d> source = RandomPoints(20, random);
  const std::vector<double> weights(source.size(), 2.0);
  const SE3 yaw(SO3::Exp(Eigen::Vector3d(0, 0, -2.5)), Eigen::Vector3d(1, 2, 3));
  std::vector<Eigen::Vector3d> target;
  for (const Eigen::Vector3d& p : source) target.push_back(yaw * p);
  EXPECT_LT((WeightedRigidAlignment(source, target, weights, true).matrix() - yaw.matrix()).norm(), 1e-12);

  const SE3 tilted(SO3::Exp(Eigen::Vector3d(0.3, 0, -2.5)), Eigen::Vector3d(1, 2, 3));
  target.clear();
  for (const Eigen::Vector3d& p : source) target.push_back(tilted * p);
  const SE3 found = WeightedRigidAlignment(source, target, weights, true);
  EXPECT_LT((found.so3().matrix().col(2) - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
}

// Four corners of a square map onto themselves, a fifth point 10 m off: with a tiny weight it leaves the
// identity (nearly) untouched, with the weight of the others it pulls the translation by 10 m / 5 = 2 m
// along its error (the centroid moves by that; the rotation can absorb only part of it).
TEST(WeightedRigidAlignment, AWeightDecidesHowMuchAPointPulls) {
  const std::vector<Eigen::Vector3d> source = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}, {2, 2, 0}};
  std::vector<Eigen::Vector3d> target = source;
  target[4] += Eigen::Vector3d(0, 0, 10);
  const SE3 light = WeightedRigidAlignment(source, target, std::vector<double>{1, 1, 1, 1, 1e-9}, false);
  EXPECT_LT((light.matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-7);
  const SE3 heavy = WeightedRigidAlignment(source, target, std::vector<double>{1, 1, 1, 1, 1}, false);
  // The centre point lies on the centroid, so it shifts the centroid (and t) by 2 m and turns nothing.
  EXPECT_LT((heavy.translation() - Eigen::Vector3d(0, 0, 2)).norm(), 1e-12);
  EXPECT_LT((heavy.so3().matrix() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace uf
