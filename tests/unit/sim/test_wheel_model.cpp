#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <vector>

#include "odometry/sim/wheel_model.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf::sim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr Stamp kSecond = kNanosecondsPerSecond;
constexpr double kCircleRadius = 8.0;  // m
constexpr double kCircleSpeed = 2.0;   // m/s
constexpr double kYawRate = kCircleSpeed / kCircleRadius;

// A vehicle driving counter-clockwise on a circle of radius R at speed v, x forward: position
// R (cos wt, sin wt, 0), yaw wt + pi/2, so body velocity (v, 0, 0) and yaw rate w = v / R. Sampled at
// 100 Hz for 40 s and fitted with 20 ms knots.
const TrajectorySpline& Circle() {
  static const TrajectorySpline spline = [] {
    Trajectory poses;
    for (int i = 0; i <= 4000; ++i) {
      const double t = i * 0.01;
      const double angle = kYawRate * t;
      poses.stamps.push_back(FromSeconds(t));
      poses.poses.emplace_back(SO3::Exp(Vector3d(0, 0, angle + std::numbers::pi / 2)),
                               Vector3d(kCircleRadius * std::cos(angle), kCircleRadius * std::sin(angle), 0));
    }
    return TrajectorySpline::FitPoses(poses, 20'000'000).value();
  }();
  return spline;
}

// The smooth 3D drive of the test support (rolling, pitching, turning), 40 s from t = 0.
const TrajectorySpline& Smooth() {
  static const TrajectorySpline spline =
      TrajectorySpline::FitPoses(test::SampleSmoothTrajectory(0, 40.0, 100.0), 50'000'000).value();
  return spline;
}

// At rest for 1000 s.
TrajectorySpline Still() {
  return TrajectorySpline::FromControlPoints(0, 1000 * kSecond, std::vector<SE3>(4, SE3()));
}

WheelSimulator MakeSimulator(const TrajectorySpline& trajectory, const WheelConfig& config,
                             const SE3& T_body_wheel = SE3(), std::uint64_t seed = 1) {
  Expected<WheelSimulator> simulator = WheelSimulator::Create(trajectory, T_body_wheel, config, seed);
  EXPECT_TRUE(simulator.ok()) << simulator.error();
  return std::move(simulator).value();
}

SimulatedWheel Simulate(const WheelSimulator& simulator, Stamp begin, Stamp end) {
  Expected<SimulatedWheel> wheel = simulator.Generate(begin, end);
  EXPECT_TRUE(wheel.ok()) << wheel.error();
  return std::move(wheel).value();
}

// (left, right) wheel rates that the odometry's (v, w) imply with its calibrated radius and baseline:
// phi_r,l = (v +- w b' / 2) / r'.
Vector2d ImpliedWheelRates(const WheelSample& sample, double radius, double baseline) {
  const double v = sample.linear_velocity.x(), w = sample.angular_velocity.z();
  return Vector2d(v - 0.5 * w * baseline, v + 0.5 * w * baseline) / radius;
}

// True (left, right) wheel rates of the differential drive at t, from the true wheel-frame motion.
Vector2d TrueWheelRates(const WheelSimulator& simulator, Stamp t) {
  const WheelTruth truth = simulator.TrueMotion(t);
  const WheelConfig& config = simulator.config();
  const double v = truth.linear_velocity.x(), w = truth.angular_velocity.z();
  return Vector2d(v - 0.5 * w * config.baseline_m, v + 0.5 * w * config.baseline_m) / config.wheel_radius_m;
}

TEST(WheelModelTest, OnACircleTheOdometryReportsSpeedAndYawRate) {
  const WheelSimulator simulator = MakeSimulator(Circle(), WheelConfig{});
  const SimulatedWheel wheel = Simulate(simulator, 1 * kSecond, 39 * kSecond);
  ASSERT_EQ(wheel.samples.size(), 38u * 50u + 1u);
  ASSERT_EQ(wheel.truth.size(), wheel.samples.size());
  EXPECT_EQ(wheel.samples[1].stamp, 1 * kSecond + 20'000'000);
  for (std::size_t i = 0; i < wheel.samples.size(); ++i) {
    const WheelSample& sample = wheel.samples[i];
    EXPECT_LT((sample.linear_velocity - Vector3d(kCircleSpeed, 0, 0)).norm(), 1e-6) << i;
    EXPECT_LT((sample.angular_velocity - Vector3d(0, 0, kYawRate)).norm(), 1e-6) << i;
    EXPECT_LT((wheel.truth[i].linear_velocity - Vector3d(kCircleSpeed, 0, 0)).norm(), 1e-6) << i;
    EXPECT_EQ(wheel.truth[i].stamp, sample.stamp);
  }
}

TEST(WheelModelTest, LeverArmAndMountRotationFollowTheRigidBodyKinematics) {
  // Wheel frame at r = (dx, dy, dz) in the body, yawed by alpha: its velocity is
  // Rz(alpha)^T (v_body + w x r) = Rz(alpha)^T (v - w dy, w dx, 0), its yaw rate w.
  const double dx = -0.7, dy = 0.3, dz = -0.4, alpha = 0.2;
  const SE3 T_body_wheel(SO3::Exp(Vector3d(0, 0, alpha)), Vector3d(dx, dy, dz));
  const WheelSimulator simulator = MakeSimulator(Circle(), WheelConfig{}, T_body_wheel);
  const Vector3d velocity = Eigen::AngleAxisd(alpha, Vector3d::UnitZ()).toRotationMatrix().transpose() *
                            Vector3d(kCircleSpeed - kYawRate * dy, kYawRate * dx, 0.0);
  const SimulatedWheel wheel = Simulate(simulator, 2 * kSecond, 12 * kSecond);
  for (std::size_t i = 0; i < wheel.samples.size(); ++i) {
    EXPECT_LT((wheel.truth[i].linear_velocity - velocity).norm(), 1e-6) << i;
    EXPECT_LT((wheel.truth[i].angular_velocity - Vector3d(0, 0, kYawRate)).norm(), 1e-6) << i;
    // Only the forward speed and the yaw rate are measured (non-holonomic).
    EXPECT_LT((wheel.samples[i].linear_velocity - Vector3d(velocity.x(), 0, 0)).norm(), 1e-6) << i;
    EXPECT_LT((wheel.samples[i].angular_velocity - Vector3d(0, 0, kYawRate)).norm(), 1e-6) << i;
  }
}

TEST(WheelModelTest, TruthIsTheNumericDerivativeOfTheWheelPose) {
  const SE3 T_body_wheel(SO3::Exp(Vector3d(0.1, -0.2, 0.7)), Vector3d(0.5, -0.3, -0.6));
  const WheelSimulator simulator = MakeSimulator(Smooth(), WheelConfig{}, T_body_wheel);
  const Stamp h = 100'000;  // 0.1 ms
  for (Stamp t = 1 * kSecond; t < 39 * kSecond; t += 1'234'567'891) {
    const auto pose = [&](Stamp s) { return Smooth().Evaluate(s).T_world_body * T_body_wheel; };
    const SE3 before = pose(t - h), now = pose(t), after = pose(t + h);
    // Central differences: v_wheel = R^T dp/dt, Hat(w) = R^T dR/dt.
    const Vector3d velocity =
        now.rotation().transpose() * (after.translation() - before.translation()) / (2e-9 * h);
    const Vector3d rate =
        Vee(now.rotation().transpose() * (after.rotation() - before.rotation())) / (2e-9 * h);
    const WheelTruth truth = simulator.TrueMotion(t);
    EXPECT_LT((truth.linear_velocity - velocity).norm(), 1e-6) << t;
    EXPECT_LT((truth.angular_velocity - rate).norm(), 1e-6) << t;
  }
}

TEST(WheelModelTest, CalibrationErrorsScaleSpeedAndYawRate) {
  const SimulatedWheel ideal = Simulate(MakeSimulator(Smooth(), WheelConfig{}), kSecond, 30 * kSecond);
  WheelConfig radius_only, baseline_only, both;
  radius_only.radius_error = 0.03;
  baseline_only.baseline_error = 0.05;
  both.radius_error = -0.02;
  both.baseline_error = -0.04;
  const SimulatedWheel radius = Simulate(MakeSimulator(Smooth(), radius_only), kSecond, 30 * kSecond);
  const SimulatedWheel baseline = Simulate(MakeSimulator(Smooth(), baseline_only), kSecond, 30 * kSecond);
  const SimulatedWheel combined = Simulate(MakeSimulator(Smooth(), both), kSecond, 30 * kSecond);
  for (std::size_t i = 0; i < ideal.samples.size(); ++i) {
    const double v = ideal.samples[i].linear_velocity.x(), w = ideal.samples[i].angular_velocity.z();
    // v' = (1 + e_r) v; w' = (1 + e_r) / (1 + e_b) w.
    EXPECT_NEAR(radius.samples[i].linear_velocity.x(), 1.03 * v, 1e-12);
    EXPECT_NEAR(radius.samples[i].angular_velocity.z(), 1.03 * w, 1e-12);
    EXPECT_NEAR(baseline.samples[i].linear_velocity.x(), v, 1e-12);
    EXPECT_NEAR(baseline.samples[i].angular_velocity.z(), w / 1.05, 1e-12);
    EXPECT_NEAR(combined.samples[i].linear_velocity.x(), 0.98 * v, 1e-12);
    EXPECT_NEAR(combined.samples[i].angular_velocity.z(), 0.98 / 0.96 * w, 1e-12);
  }
}

TEST(WheelModelTest, WheelSpeedNoiseHasTheStatisticsOfTheDifferentialDrive) {
  WheelConfig config;
  config.wheel_speed_noise_std = 0.2;
  config.radius_error = 0.1;
  config.baseline_error = -0.1;
  const SimulatedWheel wheel = Simulate(MakeSimulator(Still(), config), 0, 400 * kSecond);
  ASSERT_EQ(wheel.samples.size(), 20001u);
  // Per wheel noise n_l, n_r ~ N(0, sigma^2): v = r' (n_r + n_l) / 2 has std r' sigma / sqrt(2),
  // w = r' (n_r - n_l) / b' has std sqrt(2) r' sigma / b', and the two are uncorrelated.
  const double radius = 0.165 * 1.1, baseline = 0.555 * 0.9;
  double sv = 0, sw = 0, svv = 0, sww = 0, svw = 0;
  for (const WheelSample& sample : wheel.samples) {
    const double v = sample.linear_velocity.x(), w = sample.angular_velocity.z();
    sv += v, sw += w, svv += v * v, sww += w * w, svw += v * w;
  }
  const double n = static_cast<double>(wheel.samples.size());
  const double std_v = std::sqrt(svv / n - (sv / n) * (sv / n));
  const double std_w = std::sqrt(sww / n - (sw / n) * (sw / n));
  const double expected_v = radius * 0.2 / std::sqrt(2.0),
               expected_w = std::sqrt(2.0) * radius * 0.2 / baseline;
  test::RecordFigure("wheel_v_std_ratio", std_v / expected_v);
  EXPECT_NEAR(std_v / expected_v, 1.0, 0.03);  // standard error 1 / sqrt(2 n) = 0.5 %
  EXPECT_NEAR(std_w / expected_w, 1.0, 0.03);
  EXPECT_NEAR(sv / n, 0.0, 4.0 * expected_v / std::sqrt(n));
  EXPECT_NEAR((svw / n - sv / n * sw / n) / (std_v * std_w), 0.0, 0.03);
  // Lateral, vertical and roll/pitch are never reported.
  for (const WheelSample& sample : wheel.samples) {
    EXPECT_EQ(sample.linear_velocity.y(), 0.0);
    EXPECT_EQ(sample.linear_velocity.z(), 0.0);
    EXPECT_EQ(sample.angular_velocity.head<2>().norm(), 0.0);
  }
}

TEST(WheelModelTest, SlipTurnsTheWheelsFasterInsideTheWindow) {
  WheelConfig config;
  config.slips = {{TimeWindow{10 * kSecond, 20 * kSecond}, 0.25}};
  const SimulatedWheel wheel = Simulate(MakeSimulator(Smooth(), config), 5 * kSecond, 25 * kSecond);
  int inside = 0;
  for (std::size_t i = 0; i < wheel.samples.size(); ++i) {
    const Stamp t = wheel.samples[i].stamp;
    const double factor = (t >= 10 * kSecond && t < 20 * kSecond) ? 1.25 : 1.0;
    inside += factor > 1.0;
    EXPECT_NEAR(wheel.samples[i].linear_velocity.x(), factor * wheel.truth[i].linear_velocity.x(), 1e-12)
        << t;
    EXPECT_NEAR(wheel.samples[i].angular_velocity.z(), factor * wheel.truth[i].angular_velocity.z(), 1e-12)
        << t;
  }
  EXPECT_EQ(inside, 500);  // 10 s at 50 Hz, the begin inclusive and the end exclusive
}

TEST(WheelModelTest, FloatingWheelsKeepTheLastRatesBeforeTheWindow) {
  WheelConfig config;
  config.floats = {TimeWindow{10 * kSecond, 13 * kSecond}};
  const WheelSimulator simulator = MakeSimulator(Smooth(), config);
  const SimulatedWheel wheel = Simulate(simulator, 5 * kSecond, 20 * kSecond);
  const std::size_t last_before = 5 * 50 - 1;  // the sample at 9.98 s
  ASSERT_EQ(wheel.samples[last_before].stamp, 9'980'000'000);
  const WheelSample& held = wheel.samples[last_before];
  double largest_change = 0.0;
  for (std::size_t i = 0; i < wheel.samples.size(); ++i) {
    const Stamp t = wheel.samples[i].stamp;
    if (t >= 10 * kSecond && t < 13 * kSecond) {
      EXPECT_EQ(wheel.samples[i].linear_velocity, held.linear_velocity) << t;
      EXPECT_EQ(wheel.samples[i].angular_velocity, held.angular_velocity) << t;
      largest_change = std::max(largest_change, std::abs(wheel.truth[i].linear_velocity.x() -
                                                         wheel.truth[last_before].linear_velocity.x()));
    } else {
      EXPECT_NEAR(wheel.samples[i].linear_velocity.x(), wheel.truth[i].linear_velocity.x(), 1e-12) << t;
      EXPECT_NEAR(wheel.samples[i].angular_velocity.z(), wheel.truth[i].angular_velocity.z(), 1e-12) << t;
    }
  }
  EXPECT_GT(largest_change, 0.1);  // the true motion did change meanwhile

  // A window that starts before the first sample holds the rates of the grid extended backwards: samples
  // at 5 s + k 20 ms, window from 4.5 s, so the rates at 4.48 s.
  WheelConfig early;
  early.floats = {TimeWindow{4'500'000'000, 6 * kSecond}};
  const WheelSimulator early_simulator = MakeSimulator(Smooth(), early);
  const SimulatedWheel early_wheel = Simulate(early_simulator, 5 * kSecond, 7 * kSecond);
  const WheelTruth before = early_simulator.TrueMotion(4'480'000'000);
  EXPECT_NEAR(early_wheel.samples[0].linear_velocity.x(), before.linear_velocity.x(), 1e-12);
  EXPECT_NEAR(early_wheel.samples[49].angular_velocity.z(), before.angular_velocity.z(), 1e-12);
  EXPECT_NEAR(early_wheel.samples[50].linear_velocity.x(), early_wheel.truth[50].linear_velocity.x(), 1e-12);
}

TEST(WheelModelTest, QuantisedRatesCountWholeTicksAndStayWithinOneTickOfTheTruth) {
  WheelConfig config;
  config.encoder_resolution_ticks = 1024;
  config.radius_error = 0.02;  // the implied wheel rates below use the odometry's r', b'
  const WheelSimulator simulator = MakeSimulator(Smooth(), config);
  const SimulatedWheel wheel = Simulate(simulator, kSecond, 35 * kSecond);
  const double tick = 2.0 * std::numbers::pi / 1024, dt = 0.02;
  const double radius = 0.165 * 1.02, baseline = 0.555;
  // Mean true rate over [a, b] by Simpson's rule on 20 panels (error ~1e-9 rad/s here).
  const auto mean_rate = [&](Stamp a, Stamp b) {
    Vector2d sum = Vector2d::Zero();
    for (int j = 0; j <= 20; ++j) {
      const double weight = (j == 0 || j == 20) ? 1.0 : (j % 2 ? 4.0 : 2.0);
      sum += weight * TrueWheelRates(simulator, a + (b - a) * j / 20);
    }
    return Vector2d(sum / 60.0);
  };
  double worst = 0.0;
  Vector2d counted = Vector2d::Zero();  // ticks summed over the samples
  for (std::size_t i = 1; i < wheel.samples.size(); ++i) {
    const Vector2d rates = ImpliedWheelRates(wheel.samples[i], radius, baseline);
    const Vector2d ticks = rates * dt / tick;
    EXPECT_NEAR(ticks.x(), std::round(ticks.x()), 1e-6) << i;
    EXPECT_NEAR(ticks.y(), std::round(ticks.y()), 1e-6) << i;
    counted += ticks.array().round().matrix();
    const Vector2d error = rates - mean_rate(wheel.samples[i - 1].stamp, wheel.samples[i].stamp);
    worst = std::max(worst, error.cwiseAbs().maxCoeff() / (tick / dt));
  }
  test::RecordFigure("wheel_quantisation_worst_error_ticks", worst);
  EXPECT_LE(worst, 1.01);  // one tick, plus the trapezoid rule against Simpson (~1e-3 tick)
  EXPECT_GT(worst, 0.5);   // it does quantise
  // No drift: the counted ticks match the integrated true angle to within one tick at the end.
  Vector2d angle = Vector2d::Zero();
  for (std::size_t i = 1; i < wheel.samples.size(); ++i) {
    angle += dt * mean_rate(wheel.samples[i - 1].stamp, wheel.samples[i].stamp);
  }
  EXPECT_LE((counted - angle / tick).cwiseAbs().maxCoeff(), 1.01);
}

TEST(WheelModelTest, TheSameSeedGivesTheSameSamples) {
  WheelConfig config;
  config.wheel_speed_noise_std = 0.05;
  config.encoder_resolution_ticks = 500;
  const SimulatedWheel a = Simulate(MakeSimulator(Smooth(), config, SE3(), 42), kSecond, 10 * kSecond);
  const SimulatedWheel b = Simulate(MakeSimulator(Smooth(), config, SE3(), 42), kSecond, 10 * kSecond);
  const SimulatedWheel c = Simulate(MakeSimulator(Smooth(), config, SE3(), 43), kSecond, 10 * kSecond);
  ASSERT_EQ(a.samples.size(), c.samples.size());
  int differing = 0;
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    EXPECT_EQ(a.samples[i].linear_velocity, b.samples[i].linear_velocity);
    EXPECT_EQ(a.samples[i].angular_velocity, b.samples[i].angular_velocity);
    differing += a.samples[i].linear_velocity != c.samples[i].linear_velocity;
  }
  EXPECT_GT(differing, static_cast<int>(a.samples.size()) / 2);
}

TEST(WheelModelTest, BadConfigurationsNameTheFieldAndValue) {
  const auto error = [](const WheelConfig& config) {
    const Expected<WheelSimulator> simulator = WheelSimulator::Create(Still(), SE3(), config, 1);
    return simulator.ok() ? std::string("ok") : simulator.error();
  };
  EXPECT_EQ(error(WheelConfig{}), "ok");
  WheelConfig config;
  config.rate_hz = -5;
  EXPECT_EQ(error(config), "wheel.rate_hz: must be in (0, 10000], got -5");
  config = WheelConfig{};
  config.wheel_radius_m = 0;
  EXPECT_EQ(error(config), "wheel.wheel_radius_m: must be finite and > 0, got 0");
  config = WheelConfig{};
  config.baseline_m = std::nan("");
  EXPECT_EQ(error(config), "wheel.baseline_m: must be finite and > 0, got nan");
  config = WheelConfig{};
  config.radius_error = -1.0;
  EXPECT_EQ(error(config), "wheel.radius_error: must be finite and > -1, got -1");
  config = WheelConfig{};
  config.baseline_error = -2.0;
  EXPECT_EQ(error(config), "wheel.baseline_error: must be finite and > -1, got -2");
  config = WheelConfig{};
  config.encoder_resolution_ticks = -10;
  EXPECT_EQ(error(config), "wheel.encoder_resolution_ticks: must be finite and >= 0, got -10");
  config = WheelConfig{};
  config.wheel_speed_noise_std = -0.1;
  EXPECT_EQ(error(config), "wheel.wheel_speed_noise_std: must be finite and >= 0, got -0.1");
  config = WheelConfig{};
  config.slips = {{TimeWindow{0, kSecond}, 0.1}, {TimeWindow{2 * kSecond, kSecond}, 0.1}};
  EXPECT_EQ(error(config), "wheel.slips[1].window: end 1.000000000 s is before begin 2.000000000 s");
  config.slips = {{TimeWindow{0, kSecond}, -1.5}};
  EXPECT_EQ(error(config), "wheel.slips[0].ratio: must be finite and >= -1, got -1.5");
  config = WheelConfig{};
  config.floats = {TimeWindow{3 * kSecond, 0}};
  EXPECT_EQ(error(config), "wheel.floats[0]: end 0.000000000 s is before begin 3.000000000 s");

  const SE3 bad(SO3(), Vector3d(std::nan(""), 0, 0));
  EXPECT_FALSE(WheelSimulator::Create(Still(), bad, WheelConfig{}, 1).ok());
  const WheelSimulator simulator = MakeSimulator(Still(), WheelConfig{});
  EXPECT_FALSE(simulator.Generate(2 * kSecond, kSecond).ok());
  EXPECT_FALSE(simulator.Generate(0, 2000 * kSecond).ok());
  EXPECT_FALSE(simulator.Generate(-kSecond, kSecond).ok());
}

}  // namespace
}  // namespace uf::sim
