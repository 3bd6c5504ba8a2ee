// The camera's check against the window's predicted motion (schedule/camera_motion_check.h): hand-built
// two-view geometry for one track, and the frame's score from constructed tracks.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "odometry/estimator/schedule/camera_motion_check.h"

namespace uf::estimator {
namespace {

constexpr double kFocal = 400;  // px
constexpr double kTolerance = 4;

// Camera j at the origin, camera k 1 m forward (z) and turned 2 deg about y; T_k_j maps j's frame to k's.
SE3 ForwardMotion() {
  const SE3 T_world_k(SO3::Exp(Eigen::Vector3d(0, 2 * M_PI / 180, 0)), Eigen::Vector3d(0, 0, 1));
  return T_world_k.inverse();
}

Eigen::Vector2d Project(const SE3& T_camera_world, const Eigen::Vector3d& point) {
  return (T_camera_world * point).hnormalized();
}

TEST(CameraMotionCheck, AStaticPointAgreesWithThePredictedMotion) {
  const SE3 T_k_j = ForwardMotion();
  for (const Eigen::Vector3d& point :
       {Eigen::Vector3d(2, 1, 6), Eigen::Vector3d(-3, -0.5, 12), Eigen::Vector3d(0.5, 1.5, 4)}) {
    const TrackMotionCheck c =
        CheckTrackMotion(Project(SE3(), point), Project(T_k_j, point), T_k_j, kFocal, kTolerance);
    EXPECT_TRUE(c.agrees) << point.transpose();
    EXPECT_LT(c.error_px, 1e-6) << point.transpose();
  }
  // A far point is explained by the rotation alone: its error is the (small) parallax left.
  const Eigen::Vector3d far(30, 5, 2000);
  const TrackMotionCheck c =
      CheckTrackMotion(Project(SE3(), far), Project(T_k_j, far), T_k_j, kFocal, kTolerance);
  EXPECT_TRUE(c.agrees);
  EXPECT_LT(c.error_px, 0.5);
}

TEST(CameraMotionCheck, APointOnAnObjectCrossingTheViewDisagrees) {
  const SE3 T_k_j = ForwardMotion();
  // The point moved 0.5 m to the right between the frames (it sits on a panel passing 5 m ahead): off its
  // epipolar line by many pixels.
  const Eigen::Vector3d before(-1, 1, 5), after = before + Eigen::Vector3d(0.5, 0, 0);
  const TrackMotionCheck c =
      CheckTrackMotion(Project(SE3(), before), Project(T_k_j, after), T_k_j, kFocal, kTolerance);
  EXPECT_FALSE(c.agrees);
  EXPECT_GT(c.error_px, 10);
}

TEST(CameraMotionCheck, AFlowAgainstTheTranslationDisagreesEvenOnItsEpipolarLine) {
  // Pure forward motion, no rotation: static points flow away from the centre. A track flowing towards it
  // along the same line lies on its epipolar line (Sampson distance 0) but would be behind the cameras.
  const SE3 T_k_j(SO3(), Eigen::Vector3d(0, 0, -1));     // camera k 1 m ahead of j
  const Eigen::Vector2d x_j(0.3, 0.1), x_k = 0.8 * x_j;  // inwards, 20 % (30 px at 400 px focal)
  const TrackMotionCheck inwards = CheckTrackMotion(x_j, x_k, T_k_j, kFocal, kTolerance);
  EXPECT_FALSE(inwards.agrees);
  EXPECT_NEAR(inwards.error_px, (x_j - x_k).norm() * kFocal, 1e-9);  // the rotation-only error remains
  const TrackMotionCheck outwards = CheckTrackMotion(x_j, 1.25 * x_j, T_k_j, kFocal, kTolerance);
  EXPECT_TRUE(outwards.agrees);  // a point 5 m ahead of j, 4 m ahead of k: 1.25 x
  EXPECT_LT(outwards.error_px, 1e-9);
}

TEST(CameraMotionCheck, AFrameScoresItsAgreeingTracksTheirGridAndTheMedianError) {
  CameraScoreConfig config;
  config.residual_threshold_px = 4;
  // 80 agreeing tracks over 32 of the 64 cells (each cell of the left half), error 0.5 px, and 20 that
  // disagree by 10 px: median 0.5 px. D = 0.5 * 0 + 0.25 * (1 - 0.5) + 0.25 * 0.5 / 4 = 0.15625.
  std::vector<CheckedTrack> tracks;
  for (int i = 0; i < 80; ++i) {
    const int cell = i % 32;
    tracks.push_back({Eigen::Vector2d((cell % 4) * 80 + 10, (cell / 4) * 60 + 10), {0.5, true}});
  }
  for (int i = 0; i < 20; ++i) tracks.push_back({Eigen::Vector2d(600, 400), {10.0, false}});
  const CameraCheck check = ScoreCameraMotion(42, tracks, 640, 480, 8, config);
  EXPECT_EQ(check.stamp, 42);
  EXPECT_EQ(check.tracks_checked, 100);
  EXPECT_EQ(check.tracks_agreeing, 80);
  EXPECT_DOUBLE_EQ(check.grid_occupancy, 0.5);
  EXPECT_DOUBLE_EQ(check.motion_error_px, 0.5);
  EXPECT_NEAR(check.score, 0.15625, 1e-12);
  EXPECT_TRUE(check.active);
  // The same with 70 of them disagreeing: 30 agreeing tracks in 30 cells, median 10 px.
  // D = 0.5 * (1 - 30 / 75) + 0.25 * (1 - 30 / 64) + 0.25 = 0.6828125.
  for (int i = 0; i < 50; ++i) tracks[static_cast<std::size_t>(i)].check = {10.0, false};
  const CameraCheck bad = ScoreCameraMotion(42, tracks, 640, 480, 8, config);
  EXPECT_EQ(bad.tracks_agreeing, 30);
  EXPECT_DOUBLE_EQ(bad.grid_occupancy, 30.0 / 64);
  EXPECT_NEAR(bad.score, 0.6828125, 1e-12);
  // A diverged pose's NaN errors count as the worst, not as noise in the median.
  for (int i = 0; i < 60; ++i) tracks[static_cast<std::size_t>(i)].check.error_px = NAN;
  EXPECT_EQ(ScoreCameraMotion(42, tracks, 640, 480, 8, config).motion_error_px, INFINITY);
  // Fewer agreeing tracks than N_min: 1.
  for (int i = 50; i < 70; ++i) tracks[static_cast<std::size_t>(i)].check = {10.0, false};
  EXPECT_DOUBLE_EQ(ScoreCameraMotion(42, tracks, 640, 480, 8, config).score, 1.0);
}

}  // namespace
}  // namespace uf::estimator
