#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "odometry/sim/trajectory_spline.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf {
namespace {

using Eigen::Vector3d;

constexpr Stamp kStart = 1'700'000'000'000'000'000;  // an epoch stamp, as TUM files carry

struct FitErrors {
  double position = 0;  // m, largest |p_spline(t_k) - p_k|
  double rotation = 0;  // rad, largest angle of R_k^T R_spline(t_k)
};

FitErrors MeasureAtPoses(const TrajectorySpline& spline, const Trajectory& poses) {
  FitErrors errors;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const SE3 fitted = spline.Evaluate(poses.stamps[k]).T_world_body;
    errors.position = std::max(errors.position, (fitted.translation() - poses.poses[k].translation()).norm());
    errors.rotation = std::max(errors.rotation, (poses.poses[k].so3().inverse() * fitted.so3()).angle());
  }
  return errors;
}

TEST(SplineFitTest, PassesThroughDensePosesOfSmoothMotion) {
  // 20 s at 100 Hz, knots every 0.1 s; the yaw turns through ~13 rad. Measured: 4.5e-8 m and 4.7e-7 rad at
  // the poses, 7.7e-7 m/s in velocity.
  const Trajectory poses = test::SampleSmoothTrajectory(kStart, 20.0, 100.0);
  const Expected<TrajectorySpline> spline = TrajectorySpline::FitPoses(poses, 100'000'000);
  ASSERT_TRUE(spline.ok()) << spline.error();
  EXPECT_EQ(spline->begin(), kStart);
  EXPECT_EQ(spline->end(), poses.stamps.back());
  const FitErrors errors = MeasureAtPoses(*spline, poses);
  test::RecordFigure("max_position_error_m", errors.position);
  test::RecordFigure("max_rotation_error_rad", errors.rotation);
  EXPECT_LT(errors.position, 1e-5);
  EXPECT_LT(errors.rotation, 1e-5);
  // The motion is followed, not only the poses: velocity between the poses too.
  double worst_velocity = 0;
  for (Stamp t = kStart + 3'333'333; t < spline->end(); t += 50'000'000) {
    const double seconds = ToSeconds(t - kStart);
    worst_velocity =
        std::max(worst_velocity, (spline->Evaluate(t).velocity_world - test::SmoothVelocity(seconds)).norm());
  }
  test::RecordFigure("max_velocity_error_m_s", worst_velocity);
  EXPECT_LT(worst_velocity, 1e-4);
}

TEST(SplineFitTest, BridgesSparsePosesSmoothly) {
  // Poses at 2 Hz, knots at 0.05 s: ten control points per pose interval are decided by the smoothness
  // prior alone, and the spline still meets every pose (measured: 3e-10 m, 3e-8 rad).
  const Trajectory poses = test::SampleSmoothTrajectory(kStart, 20.0, 2.0);
  const Expected<TrajectorySpline> spline = TrajectorySpline::FitPoses(poses, 50'000'000);
  ASSERT_TRUE(spline.ok()) << spline.error();
  const FitErrors errors = MeasureAtPoses(*spline, poses);
  test::RecordFigure("max_position_error_m", errors.position);
  test::RecordFigure("max_rotation_error_rad", errors.rotation);
  EXPECT_LT(errors.position, 1e-4);
  EXPECT_LT(errors.rotation, 1e-4);
  // Between poses it stays near the true motion, as a cubic interpolant of a 2 Hz sampling does (measured:
  // 8 mm, largest in the first and last intervals where nothing bends the ends).
  double worst_between = 0;
  for (Stamp t = kStart; t < spline->end(); t += 10'000'000) {
    const SE3 truth = test::SmoothPose(ToSeconds(t - kStart));
    worst_between = std::max(worst_between,
                             (spline->Evaluate(t).T_world_body.translation() - truth.translation()).norm());
  }
  test::RecordFigure("max_position_error_between_poses_m", worst_between);
  EXPECT_LT(worst_between, 0.05);
}

TEST(SplineFitTest, FourPosesOnOneSegment) {
  const Trajectory poses = test::SampleSmoothTrajectory(kStart, 0.3, 10.0);
  const Expected<TrajectorySpline> spline = TrajectorySpline::FitPoses(poses, 1'000'000'000);
  ASSERT_TRUE(spline.ok()) << spline.error();
  EXPECT_EQ(spline->segments(), 1);
  EXPECT_TRUE(spline->Contains(poses.stamps.back()));
  EXPECT_LT(MeasureAtPoses(*spline, poses).position, 0.05);
  // 5 s knots: at this yaw rate (~1 rad/s) the rotation between control points would exceed pi, which the
  // spline cannot represent; the fit says so instead of returning a wrong turn.
  const Expected<TrajectorySpline> too_coarse = TrajectorySpline::FitPoses(poses, 5'000'000'000);
  ASSERT_FALSE(too_coarse.ok());
  EXPECT_NE(too_coarse.error().find("did not converge"), std::string::npos) << too_coarse.error();
}

// The error message of a failing fit, or "" when it succeeds.
std::string FitError(const Trajectory& poses, Stamp knot_spacing) {
  const Expected<TrajectorySpline> spline = TrajectorySpline::FitPoses(poses, knot_spacing);
  return spline.ok() ? "" : spline.error();
}

TEST(SplineFitTest, BadInputIsAnErrorNamingTheValue) {
  const Trajectory good = test::SampleSmoothTrajectory(kStart, 1.0, 10.0);
  Trajectory three = good;
  three.stamps.resize(3);
  three.poses.resize(3);
  EXPECT_NE(FitError(three, 100'000'000).find("at least 4 poses, got 3"), std::string::npos);

  Trajectory unstamped = good;
  unstamped.stamps.clear();
  EXPECT_NE(FitError(unstamped, 100'000'000).find("stamped"), std::string::npos);

  Trajectory mismatched = good;
  mismatched.stamps.pop_back();
  EXPECT_NE(FitError(mismatched, 100'000'000).find("10 stamps for 11 poses"), std::string::npos);

  Trajectory repeated = good;
  repeated.stamps[5] = repeated.stamps[4];
  EXPECT_NE(
      FitError(repeated, 100'000'000).find("pose 5 at 1700000000.400000000 s follows 1700000000.400000000 s"),
      std::string::npos)
      << FitError(repeated, 100'000'000);
  Trajectory backwards = good;
  std::swap(backwards.stamps[2], backwards.stamps[3]);
  EXPECT_NE(FitError(backwards, 100'000'000).find("strictly increasing: pose 3"), std::string::npos);

  Trajectory not_finite = good;
  not_finite.poses[7] = SE3(SO3(), Vector3d(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0));
  EXPECT_NE(FitError(not_finite, 100'000'000).find("pose 7 at 1700000000.700000000 s is not finite"),
            std::string::npos);

  EXPECT_NE(FitError(good, 0).find("knot spacing must be > 0 ns, got 0 ns"), std::string::npos);
  EXPECT_NE(FitError(good, -5).find("got -5 ns"), std::string::npos);
  EXPECT_NE(FitError(good, 1).find("knot spacing 1 ns gives more than 1e6 segments"), std::string::npos);
  EXPECT_EQ(FitError(good, 100'000'000), "");
}

}  // namespace
}  // namespace uf
