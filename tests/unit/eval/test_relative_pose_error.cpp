// RPE pair selection and errors against hand-computed cases.
#include <gtest/gtest.h>

#include "odometry/eval/relative_pose_error.h"

namespace uf {
namespace {

std::vector<SE3> Line(const std::vector<double>& xs) {
  std::vector<SE3> poses;
  for (double x : xs) poses.emplace_back(SO3(), Eigen::Vector3d(x, 0, 0));
  return poses;
}

TEST(RelativePoseError, PairsByFrames) {
  EXPECT_EQ(PairsByFrames(7, 3), (IndexPairs{{0, 3}, {3, 6}}));
  EXPECT_EQ(PairsByFrames(3, 1), (IndexPairs{{0, 1}, {1, 2}}));
  EXPECT_TRUE(PairsByFrames(3, 3).empty());
}

TEST(RelativePoseError, PairsByPathRestartTheCountAtEachEmittedIndex) {
  // Steps 0.5, 0.5, 0.5, 1.25, 0.25, 1.0 (exact in binary). Delta 1: the path reaches 1.0 at index 2,
  // restarts, reaches 1.75 at 4, restarts, reaches 1.25 at 6: emitted {2, 4, 6}. Delta 0.5: {1, 2, 3, 4, 6}.
  const auto poses = Line({0, 0.5, 1.0, 1.5, 2.75, 3.0, 4.0});
  EXPECT_EQ(PairsByPath(poses, 1.0), (IndexPairs{{2, 4}, {4, 6}}));
  EXPECT_EQ(PairsByPath(poses, 0.5), (IndexPairs{{1, 2}, {2, 3}, {3, 4}, {4, 6}}));
  EXPECT_TRUE(PairsByPath(poses, 10.0).empty());
}

TEST(RelativePoseError, HandComputedError) {
  // Reference moves 1 m along x between the poses; the estimate 1.1 m along x and turned 90 deg about z at i.
  const std::vector<SE3> reference = Line({0, 1});
  const SO3 quarter = SO3::Exp(Eigen::Vector3d(0, 0, M_PI / 2));
  const std::vector<SE3> estimate = {SE3(quarter, Eigen::Vector3d(5, 5, 0)),
                                     SE3(quarter, Eigen::Vector3d(5, 6.1, 0))};  // +1.1 along the body x
  const auto errors = RelativeTranslationErrors(reference, estimate, {{0, 1}});
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NEAR(errors[0], 0.1, 1e-12);
}

}  // namespace
}  // namespace uf
