// Stereo visual-inertial odometry (the IMU and a stereo rig) end to end on the short simulated urban drive
// of test_visual_inertial_odometry.cpp, against the simulator's ground truth and against the same drive's
// left camera alone (right frames that do not fit: visual/test_stereo_provider.cpp); a start at a steady
// speed, which the rig's depths make possible.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/unit/estimator/vio_test_support.h"

namespace uf::estimator {
namespace {

// The urban drive with a second camera 0.3 m to the right of the first (a car's stereo rig is 0.1-0.5 m
// wide; KITTI's 0.54 m).
std::filesystem::path SimulateStereo(const uf::testing::TempDir& dir, double duration_s) {
  return testing::Simulate(dir, duration_s, "",
                           [](sim::SimulationConfig& c) { c.camera.stereo_baseline_m = 0.3; });
}

TEST(StereoVisualInertialOdometry, TheRigsDepthsHoldTheScaleBetterThanOneCamera) {
  // 20 s of the urban drive (~140 m), as VisualInertialOdometry.StaticStartTracksTheTruth.
  uf::testing::TempDir dir;
  const std::filesystem::path sequence = SimulateStereo(dir, 20.0);
  const testing::VioRun stereo = testing::RunVio(sequence);
  const testing::VioRun mono =
      testing::RunVio(sequence, [](InertialOdometryConfig& c) { c.visual.stereo = false; });
  EXPECT_EQ(stereo.initialization.rfind("static", 0), 0u) << stereo.initialization;
  EXPECT_TRUE(stereo.warnings.empty()) << testing::Joined(stereo.warnings);
  EXPECT_EQ(stereo.frames, 201);  // the left frames, every one tracked
  // Every pair matched, landmarks that took their anchor's pair's depth, and the right camera's factors
  // are about half of all.
  EXPECT_EQ(stereo.factors.stereo_pairs, 201);
  EXPECT_GT(stereo.factors.stereo_depths, 500);
  EXPECT_GT(stereo.factors.stereo_factors, stereo.factors.visual.added / 3);
  EXPECT_EQ(mono.factors.stereo_pairs, 0);
  EXPECT_EQ(mono.factors.stereo_factors, 0);
  EXPECT_LT(stereo.reprojection_px, 1.0);
  // Measured: stereo ATE 0.090 m, drift 0.32 % and 0.31 deg/100 m (1343 landmarks took their pair's depth,
  // 14924 of the 28685 factors are the right camera's); the left camera alone 0.995 m, 2.37 % and 0.48
  // deg/100 m. Bounds: ~2x the stereo figures, and at most half the left camera's.
  ASSERT_GT(stereo.drift.segments, 0u);
  EXPECT_LT(stereo.ate_m, 0.2);
  EXPECT_LT(stereo.drift.t_pct, 0.7);
  EXPECT_LT(stereo.ate_m, 0.5 * mono.ate_m);
  EXPECT_LT(stereo.drift.t_pct, 0.5 * mono.drift.t_pct);
}

TEST(StereoVisualInertialOdometry, ASteadyMovingStartTakesTheRigsScale) {
  // 5 m/s along the street from the first instant, as VisualInertialOdometry.AMovingStartWaitsAndSaysWhy,
  // which one camera cannot start from: the rig's depths give the scale, the accelerometer gravity.
  uf::testing::TempDir dir;
  std::ofstream tum(dir.File("moving.tum"));
  for (int k = 0; k <= 40; ++k) tum << 100 + 0.1 * k << " " << 0.5 * k << " 0 0 0 0 0 1\n";
  tum.close();
  const testing::VioRun run =
      testing::RunVio(testing::Simulate(dir, 4.0, dir.File("moving.tum"),
                                        [](sim::SimulationConfig& c) { c.camera.stereo_baseline_m = 0.3; }),
                      nullptr, /*against_truth=*/false);
  ASSERT_EQ(run.initialization.rfind("visual-inertial (the stereo rig's scale)", 0), 0u)
      << run.initialization << "\n"
      << testing::Joined(run.warnings);
  ASSERT_GE(run.estimate.size(), 2u);
  // A straight line admits no SE3 alignment: the distance driven between the first and the last node
  // against the truth's, 5 m/s times the time between them.
  const double driven =
      (run.estimate.poses.back().translation() - run.estimate.poses.front().translation()).norm();
  const double truth = 5.0 * ToSeconds(run.estimate.stamps.back() - run.estimate.stamps.front());
  // Measured: the first node's speed 4.982 m/s, 19.95 m driven against 20.0 (every frame a node from the
  // first). Bounds: ~2-4x.
  EXPECT_EQ(run.estimate.size(), 41u);
  EXPECT_NEAR(run.first_speed_mps, 5.0, 0.05);
  EXPECT_NEAR(driven, truth, 0.01 * truth);
}

}  // namespace
}  // namespace uf::estimator
