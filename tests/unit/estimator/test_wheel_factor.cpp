// Wheel preintegration and wheel factor against independent truth: the simulator's default trajectories
// (the integrated motion against the spline's, with an error bound from the integration rules and their
// convergence order), Monte Carlo runs (covariance), central differences in the pose tangent (Jacobians), a
// small solve that recovers a 10 % wheel scale error, and bad input and configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "odometry/estimator/factors/wheel_factor.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/estimator/state/pose_manifold.h"
#include "odometry/estimator/window/dense_least_squares.h"
#include "odometry/sim/scene/default_trajectory.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/sim/wheel_model.h"

namespace uf::estimator {
namespace {

constexpr Stamp kSecond = kNanosecondsPerSecond;
constexpr Stamp kMillisecond = kSecond / 1000;

// A scene's default trajectory (12 s; standing for the first second, cruising from ~3 s) as the simulator
// fits it: a spline with knots every 0.1 s.
TrajectorySpline DefaultTrajectory(const char* scene) {
  auto poses = sim::DefaultSceneTrajectory(scene, 12.0, 3, 0);
  EXPECT_TRUE(poses.ok()) << poses.error();
  auto spline = TrajectorySpline::FitPoses(*poses, kSecond / 10);
  EXPECT_TRUE(spline.ok()) << spline.error();
  return std::move(spline).value();
}

// Wheel mounts on the body (= the imu in the simulator): a level base frame at the rear axle, behind and
// below the imu, and a tilted, offset one that gives every component of the twist.
const SE3 kRearAxle(SO3(), Eigen::Vector3d(-0.3, 0.0, -0.25));
const SE3 kTilted(SO3::Exp(Eigen::Vector3d(0.03, -0.05, 0.2)), Eigen::Vector3d(-0.6, 0.2, -0.4));

sim::WheelSimulator Wheel(const char* scene, const SE3& T_body_wheel, double rate_hz,
                          const sim::WheelConfig& base = {}) {
  sim::WheelConfig config = base;
  config.rate_hz = rate_hz;
  auto wheel = sim::WheelSimulator::Create(DefaultTrajectory(scene), T_body_wheel, config, 1);
  EXPECT_TRUE(wheel.ok()) << wheel.error();
  return std::move(wheel).value();
}

sim::SimulatedWheel Generate(const sim::WheelSimulator& wheel, Stamp begin, Stamp end) {
  auto generated = wheel.Generate(begin, end);
  EXPECT_TRUE(generated.ok()) << generated.error();
  return std::move(generated).value();
}

// The true twist as samples: all six components, what a reader of nav_msgs/Odometry could deliver.
std::vector<WheelSample> TruthSamples(const sim::SimulatedWheel& simulated) {
  std::vector<WheelSample> samples;
  for (const sim::WheelTruth& truth : simulated.truth)
    samples.push_back({truth.stamp, truth.linear_velocity, truth.angular_velocity});
  return samples;
}

SE3 WheelPose(const sim::WheelSimulator& wheel, Stamp t) {
  return wheel.trajectory().Pose(t) * wheel.T_body_wheel();
}

WheelPreintegration Preintegrate(const std::vector<WheelSample>& samples, Stamp from, Stamp to,
                                 const WheelFactorConfig& config = {}) {
  auto pre = WheelPreintegration::Between(samples, from, to, config);
  EXPECT_TRUE(pre.ok()) << pre.error();
  return std::move(pre).value();
}

struct MotionErrors {
  double rotation, position;  // rad, m
};

// The preintegrated motion against T_world_wheel(from)^-1 T_world_wheel(to) from the spline.
MotionErrors ErrorsAgainstSpline(const sim::WheelSimulator& wheel, const WheelPreintegration& pre) {
  const SE3 truth = WheelPose(wheel, pre.from()).inverse() * WheelPose(wheel, pre.to());
  return {(truth.so3().inverse() * pre.delta_R()).Log().norm(), (truth.translation() - pre.delta_p()).norm()};
}

// The leading error term of the integration rules over [from, to] at step dt, from the true motion sampled
// every millisecond (second derivatives by central differences):
//   rotation: the trapezoid rule on w errs by dt^3 / 12 |w''| per step, and the midpoint exponential drops
//     the commutator term dt^3 / 12 |w x w'| of the Magnus expansion: T dt^2 / 12 max(|w''| + |w| |w'|);
//   position: the trapezoid rule on f = R_wheel(from)^T R_wheel(t) v(t) errs by T dt^2 / 12 max |f''|, and
//     the rotation error above turns each increment: at most that angle times the path length.
MotionErrors ErrorBound(const sim::WheelSimulator& wheel, Stamp from, Stamp to, double dt) {
  const Eigen::Matrix3d R_from_T = WheelPose(wheel, from).rotation().transpose();
  const auto w = [&](Stamp t) { return wheel.TrueMotion(t).angular_velocity; };
  const auto f = [&](Stamp t) {
    return Eigen::Vector3d(R_from_T * WheelPose(wheel, t).rotation() * wheel.TrueMotion(t).linear_velocity);
  };
  const double h = ToSeconds(kMillisecond);
  double max_rotation_term = 0, max_f2 = 0, path = 0;
  for (Stamp t = from; t <= to; t += kMillisecond) {
    const Eigen::Vector3d w1 = (w(t + kMillisecond) - w(t - kMillisecond)) / (2 * h);
    const Eigen::Vector3d w2 = (w(t + kMillisecond) - 2 * w(t) + w(t - kMillisecond)) / (h * h);
    const Eigen::Vector3d f2 = (f(t + kMillisecond) - 2 * f(t) + f(t - kMillisecond)) / (h * h);
    max_rotation_term = std::max(max_rotation_term, w2.norm() + w(t).norm() * w1.norm());
    max_f2 = std::max(max_f2, f2.norm());
    path += f(t).norm() * h;
  }
  const double T = ToSeconds(to - from), k = T * dt * dt / 12;
  return {k * max_rotation_term, k * max_f2 + k * max_rotation_term * path};
}

TEST(WheelPreintegration, MatchesSplineMotionWithinTheIntegrationRulesBound) {
  // 50 Hz, the full true twist, two mounts, both scenes; 0.1 s and 1 s intervals, the latter starting and
  // ending between samples (interpolated ends). Each error stays within 1.5x the leading error term (the
  // terms of higher order are ~dt^2 = 4e-4 smaller). The bound is nearly reached over 0.1 s, where w'' is
  // about constant (urban: 1.21e-5 rad against 1.27e-5); over 1 s the errors of the steps partly cancel
  // (urban: 1.7e-5 to 4e-5 rad and 0.16 mm, against 4.6e-4 rad and 3.8 mm).
  for (const char* scene : {"urban", "wild"}) {
    for (const SE3& mount : {kRearAxle, kTilted}) {
      const sim::WheelSimulator wheel = Wheel(scene, mount, 50.0);
      const std::vector<WheelSample> samples = TruthSamples(Generate(wheel, 2 * kSecond, 10 * kSecond));
      for (const auto& [from, to] : {std::pair{4 * kSecond, 4 * kSecond + kSecond / 10},
                                     std::pair{5 * kSecond + 7'654'321, 6 * kSecond + 7'654'321},
                                     std::pair{8 * kSecond + 3'000'000, 9 * kSecond + 11'000'000}}) {
        const WheelPreintegration pre = Preintegrate(samples, from, to);
        EXPECT_EQ(pre.sum_dt(), to - from);
        const MotionErrors error = ErrorsAgainstSpline(wheel, pre);
        const MotionErrors bound = ErrorBound(wheel, from, to, 0.02);
        EXPECT_LT(error.rotation, 1.5 * bound.rotation) << scene << " from " << from;
        EXPECT_LT(error.position, 1.5 * bound.position) << scene << " from " << from;
        std::cout << scene << " [" << ToSeconds(from) << ", " << ToSeconds(to) << "] s: " << error.rotation
                  << " rad (bound " << bound.rotation << "), " << error.position << " m (bound "
                  << bound.position << "), |dp| " << pre.delta_p().norm() << " m\n";
      }
    }
  }
}

TEST(WheelPreintegration, ErrorFallsFourfoldWhenTheRateDoubles) {
  // Second order: the error ratio between 50 Hz and 100 Hz over 1 s is ~4 (ends on samples of both).
  const Stamp from = 5 * kSecond, to = 6 * kSecond;
  MotionErrors errors[2];
  for (int k = 0; k < 2; ++k) {
    const sim::WheelSimulator wheel = Wheel("wild", kTilted, k == 0 ? 50.0 : 100.0);
    errors[k] = ErrorsAgainstSpline(wheel, Preintegrate(TruthSamples(Generate(wheel, from, to)), from, to));
  }
  EXPECT_NEAR(errors[0].rotation / errors[1].rotation, 4.0, 0.5);
  EXPECT_NEAR(errors[0].position / errors[1].position, 4.0, 0.5);
}

TEST(WheelPreintegration, ScaleIsExactAndTimeOffsetShiftsTheStamps) {
  const sim::WheelSimulator wheel = Wheel("urban", kTilted, 50.0);
  const std::vector<WheelSample> samples = TruthSamples(Generate(wheel, 3 * kSecond, 6 * kSecond));
  const Stamp from = 4 * kSecond + 5'000'000, to = 5 * kSecond - 3'000'000;
  const WheelPreintegration pre = Preintegrate(samples, from, to);
  EXPECT_EQ(pre.num_samples(), 51);  // 4.02 .. 4.98 s inside, and the two interpolated ends
  // dp(s) = s dp: the samples' linear velocity times 1.1 gives 1.1 dp and the same dR.
  std::vector<WheelSample> scaled = samples;
  for (WheelSample& s : scaled) s.linear_velocity *= 1.1;
  const WheelPreintegration pre_scaled = Preintegrate(scaled, from, to);
  EXPECT_LT((pre_scaled.delta_p() - pre.ScaledDeltaP(1.1)).norm(), 1e-14 * pre.delta_p().norm());
  EXPECT_EQ(pre_scaled.delta_R().matrix(), pre.delta_R().matrix());
  // Wheel stamps 13.7 ms early, corrected by time_offset_s: the same integration.
  std::vector<WheelSample> early = samples;
  for (WheelSample& s : early) s.stamp -= 13'700'000;
  WheelFactorConfig config;
  config.time_offset_s = 0.0137;
  const WheelPreintegration shifted = Preintegrate(early, from, to, config);
  EXPECT_EQ(shifted.delta_p(), pre.delta_p());
  EXPECT_EQ(shifted.delta_R().matrix(), pre.delta_R().matrix());
  EXPECT_EQ(shifted.covariance(), pre.covariance());
  EXPECT_EQ(shifted.from(), from);
  // Uncorrected, the motion differs.
  EXPECT_GT((Preintegrate(early, from, to).delta_p() - pre.delta_p()).norm(), 1e-3);
}

TEST(WheelPreintegration, StandingStillTheCovarianceIsTheDensitiesTimesT) {
  // No motion: F = I and each step adds density^2 dt, so P = diag(density^2) T exactly.
  std::vector<WheelSample> samples;
  for (int k = 0; k <= 40; ++k) samples.push_back({k * kSecond / 40, {0, 0, 0}, {0, 0, 0}});
  const WheelFactorConfig config;
  const WheelPreintegration pre = Preintegrate(samples, kSecond / 10, 9 * kSecond / 10 + 1'000'000, config);
  const double T = pre.sum_dt_seconds();
  Vector6d expected;
  expected << config.forward_velocity_density, config.nonholonomic_velocity_density,
      config.nonholonomic_velocity_density, config.roll_pitch_rate_density, config.roll_pitch_rate_density,
      config.yaw_rate_density;
  const Matrix6d P = Matrix6d(expected.cwiseAbs2().asDiagonal()) * T;
  EXPECT_LT((pre.covariance() - P).norm(), 1e-12 * P.norm());
  EXPECT_EQ(pre.delta_p(), Eigen::Vector3d::Zero());
}

TEST(WheelPreintegration, CovarianceMatchesMonteCarlo) {
  // 2000 runs of the true twist plus white noise (variance density^2 / dt on every sample and axis) over 1 s
  // of the wild scene at 50 Hz, against the noise-free integration: the factor's residual at the truth,
  // e = [dp_ref - dp; Log(dR^T dR_ref)]. The yaw and roll/pitch noise turn into position error along the
  // path, so this checks F as well as G. The densities are a tenth of the defaults, where the second-order
  // terms are ~0.1 %: at the defaults, the soft roll/pitch noise (0.1 rad over 1 s) adds ~13 %
  // to the yaw variance at second order (products of roll and pitch errors).
  const sim::WheelSimulator wheel = Wheel("wild", kRearAxle, 50.0);
  const Stamp from = 5 * kSecond, to = 6 * kSecond;
  const std::vector<WheelSample> truth = TruthSamples(Generate(wheel, from, to));
  WheelFactorConfig config;
  for (double* density : {&config.forward_velocity_density, &config.yaw_rate_density,
                          &config.nonholonomic_velocity_density, &config.roll_pitch_rate_density})
    *density *= 0.1;
  const WheelPreintegration reference = Preintegrate(truth, from, to, config);
  Vector6d sigma;
  sigma << config.forward_velocity_density, config.nonholonomic_velocity_density,
      config.nonholonomic_velocity_density, config.roll_pitch_rate_density, config.roll_pitch_rate_density,
      config.yaw_rate_density;
  sigma /= std::sqrt(0.02);
  constexpr int kRuns = 2000;
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, 6, Eigen::Dynamic> errors(6, kRuns);
  for (int run = 0; run < kRuns; ++run) {
    std::vector<WheelSample> noisy = truth;
    for (WheelSample& s : noisy) {
      for (int k = 0; k < 3; ++k) s.linear_velocity[k] += sigma[k] * normal(random);
      for (int k = 0; k < 3; ++k) s.angular_velocity[k] += sigma[3 + k] * normal(random);
    }
    const WheelPreintegration pre = Preintegrate(noisy, from, to, config);
    errors.col(run) << reference.delta_p() - pre.delta_p(),
        (pre.delta_R().inverse() * reference.delta_R()).Log();
  }
  const Vector6d mean = errors.rowwise().mean();
  const Eigen::MatrixXd centred = errors.colwise() - mean;
  const Matrix6d sample = centred * centred.transpose() / (kRuns - 1);
  const Matrix6d& propagated = reference.covariance();
  const Vector6d ratio = sample.diagonal().cwiseQuotient(propagated.diagonal());
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(ratio(k), 1.0, 0.12) << "diagonal " << k;
  std::cout << "Monte Carlo / propagated variance: " << ratio.transpose() << "\n";
  // Every correlation agrees (the yaw with the lateral position is the strongest).
  for (int r = 0; r < 6; ++r) {
    for (int c = r + 1; c < 6; ++c) {
      const double sample_corr = sample(r, c) / std::sqrt(sample(r, r) * sample(c, c));
      const double propagated_corr = propagated(r, c) / std::sqrt(propagated(r, r) * propagated(c, c));
      EXPECT_NEAR(sample_corr, propagated_corr, 0.08) << r << ", " << c;
    }
  }
}

TEST(WheelPreintegration, RejectsBadInputNamingTheStamps) {
  const sim::WheelSimulator wheel = Wheel("urban", kRearAxle, 50.0);
  const std::vector<WheelSample> samples = TruthSamples(Generate(wheel, 2 * kSecond, 4 * kSecond));
  const WheelFactorConfig config;
  const auto message = [&](const std::vector<WheelSample>& s, Stamp from, Stamp to,
                           const WheelFactorConfig& c = {}) {
    const auto pre = WheelPreintegration::Between(s, from, to, c);
    EXPECT_FALSE(pre.ok());
    return pre.ok() ? std::string() : pre.error();
  };
  const auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  // An invalid config.
  WheelFactorConfig invalid;
  invalid.yaw_rate_density = -1;
  EXPECT_TRUE(contains(message(samples, 3 * kSecond, 4 * kSecond, invalid), "lio.wheel.yaw_rate_density"));
  // Empty or reversed interval.
  EXPECT_TRUE(contains(message(samples, 3 * kSecond, 3 * kSecond), "[3000000000, 3000000000] ns"));
  // Not covered: before, after, no samples; the time offset moves the covered span.
  std::string text = message(samples, kSecond, 3 * kSecond);
  EXPECT_TRUE(contains(text, "do not cover [1000000000, 3000000000] ns")) << text;
  EXPECT_TRUE(contains(text, "span [2000000000, 4000000000] ns")) << text;
  EXPECT_TRUE(contains(message(samples, 3 * kSecond, 4 * kSecond + 1), "[3000000000, 4000000001] ns"));
  EXPECT_TRUE(contains(message({}, 3 * kSecond, 4 * kSecond), "there are none"));
  WheelFactorConfig late;
  late.time_offset_s = 0.5;
  text = message(samples, 2 * kSecond, 3 * kSecond, late);
  EXPECT_TRUE(contains(text, "span [2500000000, 4500000000] ns")) << text;
  EXPECT_TRUE(contains(text, "time_offset_s 0.5")) << text;
  // A gap of 0.3 s (samples 3.02 .. 3.28 s dropped) inside the interval, and in the step bracketing its end.
  std::vector<WheelSample> gappy;
  for (const WheelSample& s : samples)
    if (s.stamp <= 3 * kSecond || s.stamp >= 3 * kSecond + 300 * kMillisecond) gappy.push_back(s);
  text = message(gappy, 2500 * kMillisecond, 3500 * kMillisecond);
  EXPECT_TRUE(contains(text, "gap of 0.3 s")) << text;
  EXPECT_TRUE(contains(text, "stamped 3000000000 and 3300000000 ns")) << text;
  EXPECT_TRUE(contains(text, "max_gap_s 0.2")) << text;
  EXPECT_FALSE(WheelPreintegration::Between(gappy, 2500 * kMillisecond, 3100 * kMillisecond, config).ok());
  // The same gap outside the interval, or a larger max_gap_s, is fine.
  EXPECT_TRUE(WheelPreintegration::Between(gappy, 2 * kSecond, 3 * kSecond, config).ok());
  EXPECT_TRUE(WheelPreintegration::Between(gappy, 3300 * kMillisecond, 4 * kSecond, config).ok());
  WheelFactorConfig patient;
  patient.max_gap_s = 0.35;
  EXPECT_TRUE(WheelPreintegration::Between(gappy, 2500 * kMillisecond, 3500 * kMillisecond, patient).ok());
  // A non-finite sample used, and stamps that do not increase.
  std::vector<WheelSample> bad = samples;
  bad[60].angular_velocity.z() = std::numeric_limits<double>::quiet_NaN();  // 3.2 s
  text = message(bad, 3 * kSecond, 3500 * kMillisecond);
  EXPECT_TRUE(contains(text, "non-finite velocity in the wheel sample stamped 3200000000 ns")) << text;
  EXPECT_TRUE(WheelPreintegration::Between(bad, 3500 * kMillisecond, 4 * kSecond, config).ok());
  bad = samples;
  bad[61].stamp = bad[60].stamp;
  text = message(bad, 3 * kSecond, 3500 * kMillisecond);
  EXPECT_TRUE(contains(text, "stamps must increase, got 3200000000 then 3200000000 ns")) << text;
}

TEST(WheelFactorConfig, ValidateNamesTheBadField) {
  EXPECT_TRUE(WheelFactorConfig().Validate().ok());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::pair<double WheelFactorConfig::*, const char*> fields[] = {
      {&WheelFactorConfig::forward_velocity_density, "lio.wheel.forward_velocity_density"},
      {&WheelFactorConfig::yaw_rate_density, "lio.wheel.yaw_rate_density"},
      {&WheelFactorConfig::nonholonomic_velocity_density, "lio.wheel.nonholonomic_velocity_density"},
      {&WheelFactorConfig::roll_pitch_rate_density, "lio.wheel.roll_pitch_rate_density"},
      {&WheelFactorConfig::max_gap_s, "lio.wheel.max_gap_s"},
      {&WheelFactorConfig::time_offset_s, "lio.wheel.time_offset_s"},
      {&WheelFactorConfig::scale_prior_sigma, "lio.wheel.scale_prior_sigma"}};
  for (const auto& [field, name] : fields) {
    for (const double value : {nan, -2.0, std::numeric_limits<double>::infinity()}) {
      WheelFactorConfig config;
      config.*field = value;
      const Status status = config.Validate();
      ASSERT_FALSE(status.ok()) << name << " = " << value;
      EXPECT_EQ(status.message().find(std::string(name) + ": must be "), 0u) << status.message();
      const std::string value_text = std::isnan(value) ? "nan" : std::isinf(value) ? "inf" : "-2";
      EXPECT_NE(status.message().find(value_text), std::string::npos) << status.message();
    }
  }
  // Zero densities are rejected; a zero or negative time offset within a second is fine.
  WheelFactorConfig config;
  config.yaw_rate_density = 0;
  EXPECT_FALSE(config.Validate().ok());
  config = WheelFactorConfig();
  config.time_offset_s = -0.25;
  EXPECT_TRUE(config.Validate().ok());
}

// The wheel factor's blocks.
struct Blocks {
  std::array<double, kPoseSize> pose_i, pose_j;
  double scale = 1.0;
  std::array<const double*, 3> pointers() const { return {pose_i.data(), pose_j.data(), &scale}; }
};

TEST(WheelFactor, JacobiansMatchCentralDifferencesInTheTangent) {
  // Random poses and mounts around the wild scene's motion, scale 1.07, against central differences of
  // Evaluate through PoseManifold::Plus; both the lifted ambient Jacobians (times PlusJacobian) and the
  // tangent ones.
  const sim::WheelSimulator wheel = Wheel("wild", kTilted, 50.0);
  const Stamp from = 6 * kSecond, to = 6 * kSecond + 400 * kMillisecond;
  const WheelPreintegration pre = Preintegrate(TruthSamples(Generate(wheel, from, to)), from, to);
  std::mt19937_64 random(17);
  std::normal_distribution<double> normal;
  const auto vec = [&](double s) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(random), normal(random), normal(random)) * s;
  };
  const PoseManifold manifold;
  for (int trial = 0; trial < 4; ++trial) {
    const SE3 T_imu_wheel(SO3::Exp(vec(0.5)), vec(0.5));
    const WheelFactor factor(pre, T_imu_wheel);
    Blocks x;
    x.pose_i = PoseBlock(SE3(SO3::Exp(vec(1.0)), vec(5.0)));
    x.pose_j = PoseBlock(PoseFromBlock(x.pose_i.data()) * SE3(SO3::Exp(vec(0.3)), vec(1.0)));
    x.scale = 1.07;
    const auto p = x.pointers();
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J_ambient[2];
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> J_tangent[2];
    Vector6d J_scale, J_scale_tangent, r, r_tangent;
    double* jacobians[3] = {J_ambient[0].data(), J_ambient[1].data(), J_scale.data()};
    double* tangent[3] = {J_tangent[0].data(), J_tangent[1].data(), J_scale_tangent.data()};
    ASSERT_TRUE(factor.Evaluate(p.data(), r.data(), jacobians));
    ASSERT_TRUE(factor.EvaluateTangent(p.data(), r_tangent.data(), tangent));
    EXPECT_EQ(r, r_tangent);
    const double h = 1e-6;
    for (int block = 0; block < 3; ++block) {
      const int size = block < 2 ? 6 : 1;
      Eigen::MatrixXd numeric(6, size);
      for (int k = 0; k < size; ++k) {
        Vector6d r_side[2];
        for (int side = 0; side < 2; ++side) {
          Blocks moved = x;
          const double step = side == 0 ? h : -h;
          if (block == 2) {
            moved.scale += step;
          } else {
            double delta[6] = {0, 0, 0, 0, 0, 0};
            delta[k] = step;
            auto& pose = block == 0 ? moved.pose_i : moved.pose_j;
            const auto original = pose;
            manifold.Plus(original.data(), delta, pose.data());
          }
          const auto q = moved.pointers();
          ASSERT_TRUE(factor.Evaluate(q.data(), r_side[side].data(), nullptr));
        }
        numeric.col(k) = (r_side[0] - r_side[1]) / (2 * h);
      }
      Eigen::MatrixXd analytic, analytic_tangent;
      if (block < 2) {
        Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
        manifold.PlusJacobian(p[block], plus.data());
        analytic = J_ambient[block] * plus;
        analytic_tangent = J_tangent[block];
      } else {
        analytic = J_scale;
        analytic_tangent = J_scale_tangent;
      }
      EXPECT_LT((analytic - numeric).norm(), 1e-6 * numeric.norm()) << "block " << block << "\nanalytic\n"
                                                                    << analytic << "\nnumeric\n"
                                                                    << numeric;
      EXPECT_LT((analytic_tangent - analytic).norm(), 1e-9 * numeric.norm()) << "block " << block;
    }
  }
}

// The factor's blocks at the true imu poses of the simulator (body = imu) and scale s.
Blocks TrueBlocks(const sim::WheelSimulator& wheel, Stamp from, Stamp to, double scale = 1.0) {
  Blocks x;
  x.pose_i = PoseBlock(wheel.trajectory().Pose(from));
  x.pose_j = PoseBlock(wheel.trajectory().Pose(to));
  x.scale = scale;
  return x;
}

TEST(WheelFactor, ResidualAtTheTrueMotionIsSmall) {
  // Full true twist: the unweighted residual is the integration error, within its bound (test above). The
  // odometry's own samples (v_x, 0, 0), (0, 0, w_z) miss the lateral velocity of the rear axle behind the
  // imu, and the roll, pitch and vertical motion of the scene (over 1 s up to 0.3 m vertically and 0.09 rad
  // of roll in the wild scene): the soft rows take them, so the whitened residual stays within the 6-dof
  // chi-square range (|r|^2 < 16.8 at 99 %; measured at most 3.5). The forward distance and the yaw stay
  // within one standard deviation of their firm noise (wild over 1 s: 7.5 mm against 5 cm, 5.9 mrad against
  // 10 mrad, the yaw that the unmeasured roll and pitch rates turn), and on the flatter urban scene within
  // 1 mm and 0.5 mrad (measured 0.45 mm, 0.42 mrad).
  for (const char* scene : {"urban", "wild"}) {
    const sim::WheelSimulator wheel = Wheel(scene, kRearAxle, 50.0);
    const sim::SimulatedWheel simulated = Generate(wheel, 2 * kSecond, 10 * kSecond);
    const std::vector<WheelSample> truth = TruthSamples(simulated);
    for (const Stamp length : {kSecond / 10, kSecond}) {
      for (Stamp from = 3 * kSecond; from + length <= 9 * kSecond; from += 1300 * kMillisecond) {
        const Stamp to = from + length;
        const Blocks x = TrueBlocks(wheel, from, to);
        const auto p = x.pointers();
        const WheelFactor exact(Preintegrate(truth, from, to), kRearAxle);
        const Vector6d r_exact = exact.Residual(p[0], p[1], 1.0);
        const MotionErrors bound = ErrorBound(wheel, from, to, 0.02);
        EXPECT_LT(r_exact.head<3>().norm(), 1.5 * bound.position) << scene << " at " << from;
        EXPECT_LT(r_exact.tail<3>().norm(), 1.5 * bound.rotation) << scene << " at " << from;
        const WheelFactor measured(Preintegrate(simulated.samples, from, to), kRearAxle);
        const Vector6d r = measured.Residual(p[0], p[1], 1.0);
        Vector6d weighted;
        ASSERT_TRUE(measured.Evaluate(p.data(), weighted.data(), nullptr));
        EXPECT_LT(weighted.squaredNorm(), 16.8) << scene << " " << from << ": r = " << r.transpose();
        const Vector6d sd = measured.preintegration().covariance().diagonal().cwiseSqrt();
        const double forward = std::abs(r[kWheelPosition]), yaw = std::abs(r[kWheelRotation + 2]);
        EXPECT_LT(forward, sd[kWheelPosition]) << scene << " forward at " << from;
        EXPECT_LT(yaw, sd[kWheelRotation + 2]) << scene << " yaw at " << from;
        if (scene == std::string("urban")) {
          EXPECT_LT(forward, 1e-3) << "forward at " << from;
          EXPECT_LT(yaw, 5e-4) << "yaw at " << from;
        }
      }
    }
  }
}

TEST(WheelFactor, TinySolveRecoversATenPercentScaleError) {
  // The odometry computes with a wheel radius and baseline both 1/1.1 of the truth: the reported speed is
  // v / 1.1, the yaw rate right, so the true scale is 1.1. Poses held at the truth; only the scale block is
  // free, starting at 1, with its prior (sigma 0.05) pulling towards 1 with ~1e-3 of the data's weight.
  sim::WheelConfig biased;
  biased.radius_error = biased.baseline_error = 1.0 / 1.1 - 1.0;
  const sim::WheelSimulator wheel = Wheel("urban", kRearAxle, 50.0, biased);
  const sim::SimulatedWheel simulated = Generate(wheel, 2 * kSecond, 9 * kSecond);
  const WheelFactorConfig config;
  std::vector<Blocks> blocks;
  std::vector<std::unique_ptr<WheelFactor>> factors;
  for (Stamp from = 3 * kSecond; from < 8 * kSecond; from += kSecond / 10) {
    blocks.push_back(TrueBlocks(wheel, from, from + kSecond / 10));
    factors.push_back(std::make_unique<WheelFactor>(
        Preintegrate(simulated.samples, from, from + kSecond / 10, config), kRearAxle));
  }
  double scale = 1.0;
  const WheelScalePriorFactor prior(config.scale_prior_sigma);
  DenseLeastSquares problem;
  problem.AddEuclideanBlock(&scale, 1);
  for (std::size_t k = 0; k < factors.size(); ++k)
    problem.AddResidualBlock(factors[k].get(), nullptr,
                             {blocks[k].pose_i.data(), blocks[k].pose_j.data(), &scale});
  problem.AddResidualBlock(&prior, nullptr, {&scale});
  DenseSolverOptions options;
  options.max_iterations = 20;
  options.max_time_s = 10.0;
  const DenseSolverSummary summary = problem.Solve(options);
  ASSERT_TRUE(summary.usable);
  EXPECT_LT(summary.final_cost, 0.02 * summary.initial_cost);  // left: the prior, the planar model's misfit
  EXPECT_NEAR(scale, 1.1, 2e-3);
  std::cout << "scale " << scale << " after " << summary.iterations << " iterations, cost "
            << summary.initial_cost << " -> " << summary.final_cost << "\n";
}

TEST(WheelScalePriorFactor, IsTheRelativeErrorOverSigma) {
  const WheelScalePriorFactor prior(0.05);
  const double scale = 1.1;
  const double* parameters[1] = {&scale};
  double r = 0, J = 0;
  double* jacobians[1] = {&J};
  ASSERT_TRUE(prior.Evaluate(parameters, &r, jacobians));
  EXPECT_NEAR(r, 2.0, 1e-12);
  EXPECT_NEAR(J, 20.0, 1e-12);
}

}  // namespace
}  // namespace uf::estimator
