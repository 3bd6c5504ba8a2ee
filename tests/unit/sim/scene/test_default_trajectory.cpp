// DefaultSceneTrajectory: timing, standstill, cruise, heading along the velocity, and smoothness through a
// C2 spline fit (knots every 0.1 s) with plausible accelerations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/trajectory_spline.h"

namespace uf::sim {
namespace {

struct Expectation {
  std::string name;
  double cruise;     // m/s
  double max_accel;  // m/s^2 of the fitted spline
  double max_omega;  // rad/s
  double max_tilt;   // rad, angle between body z and world z
};

class DefaultTrajectoryTest : public testing::TestWithParam<Expectation> {};

TEST_P(DefaultTrajectoryTest, TimingStandstillCruiseHeadingAndSmoothness) {
  const Expectation& e = GetParam();
  const Stamp start = 1'700'000'000'123'000'000LL;
  const double duration = 40.0;
  const auto trajectory = DefaultSceneTrajectory(e.name, duration, 9, start);
  ASSERT_TRUE(trajectory.ok()) << trajectory.error();
  const Trajectory& t = *trajectory;
  ASSERT_EQ(t.size(), 4001u);
  ASSERT_EQ(t.stamps.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    ASSERT_EQ(t.stamps[i], start + static_cast<Stamp>(i) * 10'000'000LL);
    ASSERT_TRUE(t.poses[i].translation().allFinite() && t.poses[i].rotation().allFinite());
  }
  EXPECT_EQ(t.stamps.back() - t.stamps.front(), FromSeconds(duration));
  // Standing still for the first second: identical poses.
  for (std::size_t i = 1; i <= 100; ++i) {
    EXPECT_EQ(t.poses[i].translation(), t.poses[0].translation());
    EXPECT_EQ(t.poses[i].rotation(), t.poses[0].rotation());
  }
  EXPECT_GT((t.poses[150].translation() - t.poses[0].translation()).norm(), 0.0);

  // Finite-difference velocities: cruise reached, and the body x axis along the horizontal velocity.
  double max_speed = 0.0;
  for (std::size_t i = 200; i + 1 < t.size(); ++i) {
    const Eigen::Vector3d v = (t.poses[i + 1].translation() - t.poses[i - 1].translation()) / 0.02;
    max_speed = std::max(max_speed, v.norm());
    const Eigen::Vector3d x = t.poses[i].rotation().col(0);
    const double heading_error =
        std::remainder(std::atan2(x.y(), x.x()) - std::atan2(v.y(), v.x()), 2 * M_PI);
    ASSERT_LT(std::abs(heading_error), 1e-3) << "pose " << i;
    ASSERT_GT(t.poses[i].rotation().col(2).z(), std::cos(e.max_tilt)) << "tilt at " << i;
  }
  EXPECT_GT(max_speed, 0.95 * e.cruise);
  EXPECT_LT(max_speed, 1.25 * e.cruise);

  // A C2 spline with 0.1 s knots follows it closely and has plausible derivatives.
  const auto spline = TrajectorySpline::FitPoses(t, 100'000'000);
  ASSERT_TRUE(spline.ok()) << spline.error();
  double max_accel = 0.0, max_omega = 0.0, max_position_error = 0.0;
  for (std::size_t i = 0; i < t.size(); i += 5) {
    if (!spline->Contains(t.stamps[i])) continue;
    const TrajectorySpline::State s = spline->Evaluate(t.stamps[i]);
    max_accel = std::max(max_accel, s.acceleration_world.norm());
    max_omega = std::max(max_omega, s.angular_velocity_body.norm());
    max_position_error =
        std::max(max_position_error, (s.T_world_body.translation() - t.poses[i].translation()).norm());
  }
  EXPECT_LT(max_position_error, 0.01);
  EXPECT_LT(max_accel, e.max_accel);
  EXPECT_LT(max_omega, e.max_omega);
  EXPECT_GT(max_omega, 0.02);  // it does rotate (observability)
}

TEST_P(DefaultTrajectoryTest, SuspensionOscillatesAboutTheRestAttitude) {
  // The body pitches on its suspension about its rest attitude on the road: the angle between the
  // velocity and the body x axis, atan2(v_z, v_x) in the body frame, averages to zero while cruising (after
  // the ramp; the speed's wobble has a zero-mean acceleration, so its squat averages out too). Its mean was
  // 0.004-0.05 rad when the waves were shifted to zero at the start (a tilt against the road that appeared
  // only while moving, which no wheel model can explain); now below 0.3 mrad. It does oscillate: RMS above
  // 2 mrad.
  const Expectation& e = GetParam();
  for (std::uint64_t seed : {1, 2, 3}) {
    const auto trajectory = DefaultSceneTrajectory(e.name, 60.0, seed, 0);
    ASSERT_TRUE(trajectory.ok()) << trajectory.error();
    const Trajectory& t = *trajectory;
    double sum = 0.0, sum_squared = 0.0;
    int count = 0;
    for (std::size_t i = 1000; i + 1 < t.size(); ++i) {  // from 10 s on
      const Eigen::Vector3d v_world = (t.poses[i + 1].translation() - t.poses[i - 1].translation()) / 0.02;
      const Eigen::Vector3d v = t.poses[i].rotation().transpose() * v_world;
      const double angle = std::atan2(v.z(), v.x());
      sum += angle;
      sum_squared += angle * angle;
      ++count;
    }
    const double mean = sum / count, rms = std::sqrt(sum_squared / count);
    EXPECT_LT(std::abs(mean), 2e-3) << e.name << " seed " << seed << " (rms " << rms << ")";
    EXPECT_GT(rms, 2e-3) << e.name << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, DefaultTrajectoryTest,
                         testing::Values(Expectation{"urban", 8.0, 5.0, 1.0, 0.1},
                                         Expectation{"wild", 3.0, 5.0, 1.5, 0.3},
                                         Expectation{"warehouse", 1.5, 2.0, 1.0, 0.03},
                                         Expectation{"corridor", 1.2, 2.0, 0.5, 0.03},
                                         Expectation{"tunnel", 12.0, 5.0, 0.5, 0.08}),
                         [](const auto& info) { return info.param.name; });

TEST(DefaultSceneTrajectory, SeededAndDifferentPerSeed) {
  const auto a = DefaultSceneTrajectory("urban", 30.0, 1, 0), b = DefaultSceneTrajectory("urban", 30.0, 1, 0);
  const auto c = DefaultSceneTrajectory("urban", 30.0, 2, 0);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->poses.back().translation(), b->poses.back().translation());
  EXPECT_NE(a->poses.back().translation(), c->poses.back().translation());
}

TEST(DefaultSceneTrajectory, BadInput) {
  const auto unknown = DefaultSceneTrajectory("moon", 30.0, 1, 0);
  ASSERT_FALSE(unknown.ok());
  for (const std::string_view name : SceneNames()) {
    EXPECT_NE(unknown.error().find(std::string(name)), std::string::npos);
  }
  const auto short_one = DefaultSceneTrajectory("urban", 1.0, 1, 0);
  ASSERT_FALSE(short_one.ok());
  EXPECT_NE(short_one.error().find("duration_s"), std::string::npos);
  EXPECT_FALSE(DefaultSceneTrajectory("urban", std::nan(""), 1, 0).ok());
}

}  // namespace
}  // namespace uf::sim
