// The trajectory against its GNSS fixes (odometry/eval/gnss_track_error.h) on a drive with known truth:
// exact fixes give zero error, a known offset of the trajectory is found unaligned and removed by the fit,
// and the segment error is the known drift over the known track.
#include <gtest/gtest.h>

#include "odometry/eval/gnss_track_error.h"
#include "tests/unit/eval/gnss_test_support.h"

namespace uf {
namespace {

using testing::Drive;
using testing::Fixes;
using testing::kTrueOrigin;

const Eigen::Vector3d kLever(0.5, 0, 1.2);

// The drive in ENU at kTrueOrigin, its fixes without noise.
struct Georeferenced {
  SE3 T_enu_world{SO3::Exp(Eigen::Vector3d(0, 0, 0.7)), Eigen::Vector3d(3, -4, 1)};
  Trajectory enu;
  std::vector<GnssFix> fixes;
  Georeferenced() {
    const Trajectory drive = Drive();
    enu = drive;
    for (SE3& pose : enu.poses) pose = T_enu_world * pose;
    fixes = Fixes(drive, T_enu_world, kLever, [](std::size_t) { return 0.0; });
  }
};

TEST(GnssTrackError, ExactFixesOfAGeoreferencedTrajectoryGiveNoError) {
  const Georeferenced g;
  const SE3 lever(SO3(), kLever);
  Expected<GnssTrackError> error = CompareWithGnssTrack(g.enu, g.fixes, lever, kTrueOrigin, true);
  ASSERT_TRUE(error.ok()) << error.error();
  EXPECT_FALSE(error->aligned);
  EXPECT_EQ(error->fixes, 151);
  EXPECT_LT(error->horizontal_rmse_m, 1e-6);
  EXPECT_LT(error->vertical_rmse_m, 1e-6);
  ASSERT_TRUE(error->segment_error_percent);
  EXPECT_LT(*error->segment_error_percent, 1e-6);
  EXPECT_GT(error->track_length_m, 120);  // 30 s at 4 m/s plus the S-curve's sway
}

TEST(GnssTrackError, AnOffsetShowsUnalignedAndTheFitRemovesIt) {
  Georeferenced g;
  const SE3 lever(SO3(), kLever);
  // Every pose 3 m east and 4 m up: horizontal RMSE 3, vertical 4, and no segment error (a constant offset).
  for (SE3& pose : g.enu.poses) pose = SE3(pose.so3(), pose.translation() + Eigen::Vector3d(3, 0, 4));
  Expected<GnssTrackError> offset = CompareWithGnssTrack(g.enu, g.fixes, lever, kTrueOrigin, true);
  ASSERT_TRUE(offset.ok()) << offset.error();
  EXPECT_NEAR(offset->horizontal_rmse_m, 3, 1e-6);
  EXPECT_NEAR(offset->vertical_rmse_m, 4, 1e-6);
  EXPECT_LT(*offset->segment_error_percent, 1e-6);
  // Not georeferenced: the fit (yaw and translation) removes the offset and the world's own yaw. Its ENU
  // frame sits at the first fix, tilted against the truth's by that fix's distance over the Earth's radius
  // (~1e-6 rad), which a yaw and a translation cannot absorb: micrometres over the drive.
  Expected<GnssTrackError> fitted = CompareWithGnssTrack(Drive(), g.fixes, lever, std::nullopt, true);
  ASSERT_TRUE(fitted.ok()) << fitted.error();
  EXPECT_TRUE(fitted->aligned);
  EXPECT_LT(fitted->horizontal_rmse_m, 1e-4);
  EXPECT_LT(fitted->vertical_rmse_m, 1e-4);
}

TEST(GnssTrackError, AScaleDriftIsTheSegmentError) {
  // The trajectory 2 % longer than the truth about its start (a scale drift of the odometry): every
  // displacement is 2 % long, so the error over each segment is 2 % of its length.
  Georeferenced g;
  const SE3 lever(SO3(), Eigen::Vector3d::Zero());
  g.fixes = Fixes(Drive(), g.T_enu_world, Eigen::Vector3d::Zero(), [](std::size_t) { return 0.0; });
  const Eigen::Vector3d start = g.enu.poses.front().translation();
  for (SE3& pose : g.enu.poses) pose = SE3(pose.so3(), start + 1.02 * (pose.translation() - start));
  Expected<GnssTrackError> error = CompareWithGnssTrack(g.enu, g.fixes, lever, kTrueOrigin, true, 50);
  ASSERT_TRUE(error.ok()) << error.error();
  ASSERT_TRUE(error->segment_error_percent);
  // Each segment's error is 2 % of its chord, divided by its length along the track (the arc): on the
  // S-curve (8 m of sway over 120 m) the chord is within 2.5 % of the arc over 50 m, so 1.95 % to 2 %.
  EXPECT_LE(*error->segment_error_percent, 2.0 + 1e-9);
  EXPECT_GT(*error->segment_error_percent, 1.95);
}

TEST(GnssTrackError, NoFixInTheTrajectorysSpanIsAnError) {
  Georeferenced g;
  for (GnssFix& fix : g.fixes) fix.stamp += 100 * testing::kSecond;
  EXPECT_FALSE(CompareWithGnssTrack(g.enu, g.fixes, SE3(), kTrueOrigin, true).ok());
}

}  // namespace
}  // namespace uf
