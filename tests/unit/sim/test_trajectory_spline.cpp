#include <gtest/gtest.h>

#include <algorithm>

#include "odometry/sim/trajectory_spline.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf {
namespace {

using Eigen::Vector3d;

constexpr Stamp kSpacing = 100'000'000;  // 0.1 s between knots

// Brisk motion: ~3 m/s, ~2.5 rad/s about changing axes, jerk up to ~1e3 m/s^3 (random control points, 0.1 s
// knots).
TrajectorySpline TestSpline() { return test::RandomSpline(11, 14, kSpacing); }

// Stamps strictly inside segments, at least 3 ms away from every knot, so central differences of step up to
// 1 ms never straddle one (the third derivative jumps there).
std::vector<Stamp> InteriorStamps(const TrajectorySpline& spline) {
  std::vector<Stamp> stamps;
  for (Stamp t = spline.begin() + 3'000'000; t < spline.end(); t += 7'300'000) {
    const Stamp into_segment = (t - spline.begin()) % kSpacing;
    if (into_segment > 3'000'000 && into_segment < kSpacing - 3'000'000) stamps.push_back(t);
  }
  return stamps;
}

TEST(TrajectorySplineTest, SpansControlPointsMinusThreeSegments) {
  const TrajectorySpline spline = TestSpline();
  EXPECT_EQ(spline.segments(), 11);
  EXPECT_EQ(spline.begin(), 1'000'000'000);
  EXPECT_EQ(spline.end(), 1'000'000'000 + 11 * kSpacing);
  EXPECT_TRUE(spline.Contains(spline.end()));
  EXPECT_FALSE(spline.Contains(spline.end() + 1));
  EXPECT_FALSE(spline.Contains(spline.begin() - 1));
  // At a knot the position is (c_{i-1} + 4 c_i + c_{i+1}) / 6 of the control point sitting there.
  const std::vector<SE3>& c = spline.control_points();
  const Vector3d expected = (c[4].translation() + 4 * c[5].translation() + c[6].translation()) / 6.0;
  EXPECT_LT((spline.Evaluate(spline.begin() + 4 * kSpacing).T_world_body.translation() - expected).norm(),
            1e-14);
}

TEST(TrajectorySplineTest, LinearDerivativesMatchCentralDifferencesOfPositions) {
  // Within a segment the position is a cubic in t: the central first difference errs by h^2 jerk / 6
  // (measured 1.5e-6 m/s at h = 0.1 ms), the second difference only by rounding, eps |p| / h^2 (measured
  // 5e-10 m/s^2 at h = 1 ms).
  const TrajectorySpline spline = TestSpline();
  double worst_velocity = 0, worst_acceleration = 0;
  for (Stamp t : InteriorStamps(spline)) {
    const auto position = [&](Stamp s) { return spline.Evaluate(s).T_world_body.translation(); };
    const TrajectorySpline::State state = spline.Evaluate(t);
    const Stamp h1 = 100'000, h2 = 1'000'000;
    const Vector3d velocity = (position(t + h1) - position(t - h1)) / (2 * ToSeconds(h1));
    const Vector3d acceleration =
        (position(t + h2) - 2 * position(t) + position(t - h2)) / std::pow(ToSeconds(h2), 2);
    worst_velocity = std::max(worst_velocity, (state.velocity_world - velocity).norm());
    worst_acceleration = std::max(worst_acceleration, (state.acceleration_world - acceleration).norm());
  }
  test::RecordFigure("max_velocity_error_m_s", worst_velocity);
  test::RecordFigure("max_acceleration_error_m_s2", worst_acceleration);
  EXPECT_LT(worst_velocity, 1e-5);
  EXPECT_LT(worst_acceleration, 1e-6);
}

TEST(TrajectorySplineTest, AngularDerivativesMatchCentralDifferencesOfRotations) {
  // omega ~ Log(R(t - h)^T R(t + h)) / 2h errs by O(h^2 (|d2omega/dt2| + |omega x alpha|)) (measured
  // 5e-8 rad/s at h = 20 us); alpha is the central difference of that numeric omega, whose rounding error
  // is ~eps / h^2 (measured 5e-7 rad/s^2).
  const TrajectorySpline spline = TestSpline();
  const Stamp h = 20'000;
  const auto numeric_omega = [&](Stamp s) {
    const SO3 before = spline.Evaluate(s - h).T_world_body.so3(),
              after = spline.Evaluate(s + h).T_world_body.so3();
    return Vector3d((before.inverse() * after).Log() / (2 * ToSeconds(h)));
  };
  double worst_omega = 0, worst_alpha = 0, largest_omega = 0, largest_alpha = 0;
  for (Stamp t : InteriorStamps(spline)) {
    const TrajectorySpline::State state = spline.Evaluate(t);
    const Vector3d alpha = (numeric_omega(t + h) - numeric_omega(t - h)) / (2 * ToSeconds(h));
    worst_omega = std::max(worst_omega, (state.angular_velocity_body - numeric_omega(t)).norm());
    worst_alpha = std::max(worst_alpha, (state.angular_acceleration_body - alpha).norm());
    largest_omega = std::max(largest_omega, state.angular_velocity_body.norm());
    largest_alpha = std::max(largest_alpha, state.angular_acceleration_body.norm());
  }
  EXPECT_GT(largest_omega, 2.0);  // the test motion really turns and accelerates
  EXPECT_GT(largest_alpha, 20.0);
  test::RecordFigure("max_angular_velocity_error_rad_s", worst_omega);
  test::RecordFigure("max_angular_acceleration_error_rad_s2", worst_alpha);
  EXPECT_LT(worst_omega, 1e-6);
  EXPECT_LT(worst_alpha, 1e-4);
}

TEST(TrajectorySplineTest, SecondDerivativesAreContinuousAtKnots) {
  // One nanosecond either side of each knot, the two neighbouring segments agree to the change in 1 ns
  // (|jerk| 1e-9 ~ 1e-7). The jerk itself jumps (the spline is C2, not C3): the one-sided differences prove
  // the comparison can see a discontinuity of that size.
  const TrajectorySpline spline = TestSpline();
  double largest_jerk_jump = 0;
  for (int knot = 1; knot < spline.segments(); ++knot) {
    const Stamp t = spline.begin() + knot * kSpacing;
    const TrajectorySpline::State left = spline.Evaluate(t - 1), right = spline.Evaluate(t + 1);
    EXPECT_LT((left.T_world_body.translation() - right.T_world_body.translation()).norm(), 1e-7) << knot;
    EXPECT_LT((left.T_world_body.so3().inverse() * right.T_world_body.so3()).angle(), 1e-7) << knot;
    EXPECT_LT((left.velocity_world - right.velocity_world).norm(), 1e-6) << knot;
    EXPECT_LT((left.acceleration_world - right.acceleration_world).norm(), 1e-5) << knot;
    EXPECT_LT((left.angular_velocity_body - right.angular_velocity_body).norm(), 1e-6) << knot;
    EXPECT_LT((left.angular_acceleration_body - right.angular_acceleration_body).norm(), 1e-5) << knot;
    const Stamp h = 1'000'000;
    const Vector3d a = spline.Evaluate(t).acceleration_world;
    const Vector3d jerk_before = (a - spline.Evaluate(t - h).acceleration_world) / ToSeconds(h);
    const Vector3d jerk_after = (spline.Evaluate(t + h).acceleration_world - a) / ToSeconds(h);
    largest_jerk_jump = std::max(largest_jerk_jump, (jerk_after - jerk_before).norm());
  }
  EXPECT_GT(largest_jerk_jump, 10.0);
}

TEST(TrajectorySplineTest, EqualControlPointsHoldStill) {
  const SE3 pose(SO3::Exp(Vector3d(0.1, 0.2, 0.3)), Vector3d(1.0, 2.0, 3.0));
  const TrajectorySpline spline = TrajectorySpline::FromControlPoints(0, kSpacing, std::vector<SE3>(5, pose));
  const TrajectorySpline::State state = spline.Evaluate(kSpacing + 12345);
  EXPECT_LT((state.T_world_body.matrix() - pose.matrix()).norm(), 1e-14);
  EXPECT_LT(state.velocity_world.norm() + state.acceleration_world.norm(), 1e-14);
  EXPECT_LT(state.angular_velocity_body.norm() + state.angular_acceleration_body.norm(), 1e-14);
}

}  // namespace
}  // namespace uf
