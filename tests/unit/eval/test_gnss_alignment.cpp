// Georeferencing a trajectory with GNSS fixes: fixes made from a known T_enu_world (plus noise) give it back;
// too few fixes, too short a path and inconsistent fixes are refused with the reason.
#include <gtest/gtest.h>

#include <cmath>

#include "gnss_test_support.h"
#include "odometry/eval/gnss_alignment.h"

namespace uf {
namespace {

using testing::Drive;

const Eigen::Vector3d kLever(0.1, 0.0, 0.4);  // antenna in the body frame

// Fixes at 5 Hz of the antenna placed by T_enu_world, with Gaussian noise of `sigma` per axis.
std::vector<GnssFix> Fixes(const Trajectory& trajectory, const SE3& T_enu_world, double sigma) {
  return testing::Fixes(trajectory, T_enu_world, kLever, [sigma](std::size_t) { return sigma; });
}

// Largest distance, over the trajectory, between where the alignment puts the body and where it truly is
// (both taken to the true ENU frame through WGS84).
double WorstError(const Trajectory& trajectory, const GnssAlignment& aligned, const SE3& T_enu_world) {
  double worst = 0;
  for (const SE3& pose : trajectory.poses) {
    const Eigen::Vector3d estimated = testing::AlignedInTrueEnu(aligned, pose.translation());
    worst = std::max(worst, (estimated - T_enu_world * pose.translation()).norm());
  }
  return worst;
}

TEST(GnssAlignment, GravityAlignedRecoversYawAndTranslation) {
  const Trajectory trajectory = Drive();
  const SE3 T_enu_world(SO3::Exp(Eigen::Vector3d(0, 0, 0.7)), Eigen::Vector3d(120, -40, 3));
  GnssAlignmentOptions options;
  options.T_body_antenna = SE3(SO3(), kLever);
  auto aligned = AlignToGnss(trajectory, Fixes(trajectory, T_enu_world, 0.02), options);
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_EQ(aligned->fixes_used, 151);
  EXPECT_NEAR(aligned->rms_m, 0.02 * std::sqrt(3.0), 0.01);
  EXPECT_LT(WorstError(trajectory, *aligned, T_enu_world), 0.02);  // 2 cm noise, 151 fixes over 120 m
}

TEST(GnssAlignment, FullRotationForAWorldThatIsNotLevel) {
  const Trajectory trajectory = Drive();
  const SE3 T_enu_world(SO3::Exp(Eigen::Vector3d(0.05, -0.08, 2.0)), Eigen::Vector3d(-7, 15, -2));
  GnssAlignmentOptions options;
  options.T_body_antenna = SE3(SO3(), kLever);
  options.gravity_aligned = false;
  auto aligned = AlignToGnss(trajectory, Fixes(trajectory, T_enu_world, 0.02), options);
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_LT(WorstError(trajectory, *aligned, T_enu_world), 0.05);
  // The yaw-only model cannot take the tilt: its residual shows it.
  options.gravity_aligned = true;
  auto level = AlignToGnss(trajectory, Fixes(trajectory, T_enu_world, 0.02), options);
  ASSERT_TRUE(level.ok()) << level.error();
  EXPECT_GT(level->rms_m, 0.5);
}

TEST(GnssAlignment, RefusesWhatCannotFixTheHeading) {
  const Trajectory trajectory = Drive();
  const SE3 T_enu_world;
  std::vector<GnssFix> fixes = Fixes(trajectory, T_enu_world, 0.02);
  auto few = AlignToGnss(trajectory, std::span<const GnssFix>(fixes).first(5));
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.error().find("5 fixes"), std::string::npos) << few.error();
  auto short_path = AlignToGnss(trajectory, std::span<const GnssFix>(fixes).first(12));  // 2.4 s, ~9 m
  ASSERT_FALSE(short_path.ok());
  EXPECT_NE(short_path.error().find("for the heading"), std::string::npos) << short_path.error();
  auto noisy = AlignToGnss(trajectory, Fixes(trajectory, T_enu_world, 30.0));
  ASSERT_FALSE(noisy.ok());
  EXPECT_NE(noisy.error().find("residual RMS"), std::string::npos) << noisy.error();
  for (GnssFix& fix : fixes) fix.status = GnssFixStatus::kNoFix;
  EXPECT_FALSE(AlignToGnss(trajectory, fixes).ok());
}

}  // namespace
}  // namespace uf
