// The camera's degeneracy score: hand-computed values of the paper's formula, and on simulated frames the
// scripted occluder (a dark band over a third of the image) raises it where it slides across the lens.
#include <gtest/gtest.h>

#include "odometry/estimator/schedule/camera_degeneracy.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "tests/unit/estimator/visual/simulated_camera.h"

namespace uf::estimator {
namespace {

TEST(CameraDegeneracy, IsThePapersWeightedSum) {
  // 75 tracks or more, every cell, no error: 0. 30 tracks: 0.5 (1 - 30 / 75) = 0.3; occupancy 0.6 adds
  // 0.25 * 0.4 = 0.1; an error of 0.4 px adds 0.25 * 0.4 = 0.1: 0.5.
  EXPECT_DOUBLE_EQ(ScoreCameraFrame(150, 1.0, 0.0).score, 0.0);
  EXPECT_NEAR(ScoreCameraFrame(30, 0.6, 0.4).score, 0.5, 1e-12);
  EXPECT_NEAR(ScoreCameraFrame(30, 0.6, 3.0).score, 0.3 + 0.1 + 0.25, 1e-12);  // the error term saturates
  EXPECT_DOUBLE_EQ(ScoreCameraFrame(19, 1.0, 0.0).score, 1.0);                 // below N_min
  const CameraDegeneracy d = ScoreCameraFrame(40, 0.5, 0.2);
  EXPECT_EQ(d.tracks, 40);
  EXPECT_DOUBLE_EQ(d.grid_occupancy, 0.5);
  EXPECT_DOUBLE_EQ(d.epipolar_error_px, 0.2);
}

TEST(CameraDegeneracy, RisesWhileAnOccluderCoversTheLens) {
  const Stamp t0 = 1'700'000'000'000'000'000;  // the simulator's default start
  const Stamp occluded_begin = t0 + 4'000'000'000, occluded_end = t0 + 6'000'000'000;
  const auto camera = test::SimulatedCamera::Create("urban", 8.0, 3, [&](sim::CameraConfig& c) {
    c.occlusions.push_back({occluded_begin, occluded_end});
  });
  ASSERT_NE(camera, nullptr);
  auto tracker = FeatureTracker::Create(camera->model(), {});
  ASSERT_TRUE(tracker);
  double inside = 0, outside = 0;
  int n_inside = 0, n_outside = 0;
  for (Stamp t = t0 + 2'000'000'000; t < t0 + 7'000'000'000; t += 100'000'000) {
    auto frame = tracker->Track(t, camera->Render(t));
    ASSERT_TRUE(frame);
    if (t < t0 + 2'500'000'000) continue;  // the first frames build up the tracks
    const FrameTrackStats& s = frame->stats;
    const double d = ScoreCameraFrame(s.tracked, s.grid_occupancy, s.epipolar_error_px).score;
    if (t >= occluded_begin && t < occluded_end)
      inside += d, ++n_inside;
    else if (t < occluded_begin || t >= occluded_end + 500'000'000)
      outside += d, ++n_outside;
  }
  ASSERT_GT(n_inside, 10);
  ASSERT_GT(n_outside, 10);
  EXPECT_LT(outside / n_outside, 0.15);
  EXPECT_GT(inside / n_inside, outside / n_outside + 0.1);
}

}  // namespace
}  // namespace uf::estimator
