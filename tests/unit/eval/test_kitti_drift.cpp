// KITTI drift against hand-computed cases: a 1 % scale error gives 1 % translational drift and no rotation;
// a constant heading error accumulates no relative rotation, a per-metre yaw rate does; the path scale is the
// chords' ratio whatever rigid motion the estimate is off by.
#include <gtest/gtest.h>

#include "odometry/eval/kitti_drift.h"

namespace uf {
namespace {

TEST(KittiDrift, ScaleErrorIsTheTranslationalDrift) {
  std::vector<SE3> reference, estimate;
  for (int i = 0; i <= 1000; ++i) {  // 1 m per frame along x
    reference.emplace_back(SO3(), Eigen::Vector3d(i, 0, 0));
    estimate.emplace_back(SO3(), Eigen::Vector3d(1.01 * i, 0, 0));
  }
  const KittiDrift drift = ComputeKittiDrift(reference, estimate);
  // Segment of length L from frame f ends at the first frame with distance > L: L + 1 frames, error 0.01 (L +
  // 1). Mean over segments of 0.01 (L + 1) / L, in percent.
  double expected = 0;
  std::size_t segments = 0;
  for (int first = 0; first <= 1000; first += 10)
    for (int length = 100; length <= 800; length += 100)
      if (first + length + 1 <= 1000) {
        expected += 1.0 * (length + 1) / length;
        ++segments;
      }
  EXPECT_EQ(drift.segments, segments);
  EXPECT_NEAR(drift.t_pct, expected / segments, 1e-9);
  EXPECT_NEAR(drift.r_deg_per_100m, 0, 1e-9);
  EXPECT_NEAR(drift.scale_ppm, 1e4, 1e-6);  // every chord 1.01 times the reference's
}

TEST(KittiDrift, PathScaleHasASignAndIgnoresARigidMotion) {
  // A circle of radius 100 m, one frame per metre, and the same circle 0.5 % smaller, turned by 30 deg about
  // z and moved: every chord of the estimate is 0.995 times the reference's.
  std::vector<SE3> reference, estimate;
  const SE3 rigid(SO3::Exp(Eigen::Vector3d(0, 0, M_PI / 6)), Eigen::Vector3d(5, -3, 2));
  for (int i = 0; i <= 600; ++i) {
    const double a = i / 100.0;
    const SE3 pose(SO3::Exp(Eigen::Vector3d(0, 0, a)), 100.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0));
    reference.push_back(pose);
    estimate.push_back(rigid * SE3(pose.so3(), 0.995 * pose.translation()));
  }
  const KittiDrift drift = ComputeKittiDrift(reference, estimate);
  ASSERT_GT(drift.segments, 0u);
  EXPECT_NEAR(drift.scale_ppm, -5000, 1e-6);
  EXPECT_NEAR(ComputeKittiDrift(reference, reference).scale_ppm, 0, 1e-9);
}

TEST(KittiDrift, YawErrorPerMetre) {
  // The estimate turns by 0.001 rad per frame about z while translating like the reference in its own frame.
  std::vector<SE3> reference, estimate;
  SE3 pose;
  for (int i = 0; i <= 300; ++i) {
    reference.emplace_back(SO3(), Eigen::Vector3d(i, 0, 0));
    estimate.push_back(pose);
    pose = pose * SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.001)), Eigen::Vector3d(1, 0, 0));
  }
  const KittiDrift drift = ComputeKittiDrift(reference, estimate);
  ASSERT_GT(drift.segments, 0u);
  // Every segment of length L spans L + 1 frames: rotation error 0.001 (L + 1) rad.
  double expected = 0;
  for (int first = 0; first <= 300; first += 10)
    for (int length = 100; length <= 800; length += 100)
      if (first + length + 1 <= 300) expected += 0.001 * (length + 1) / length;
  EXPECT_NEAR(drift.r_deg_per_100m, 100 * 180 / M_PI * expected / drift.segments, 1e-9);
}

TEST(KittiDrift, ShortPathHasNoSegment) {
  std::vector<SE3> poses;
  for (int i = 0; i < 50; ++i) poses.emplace_back(SO3(), Eigen::Vector3d(i, 0, 0));
  EXPECT_EQ(ComputeKittiDrift(poses, poses).segments, 0u);
}

}  // namespace
}  // namespace uf
