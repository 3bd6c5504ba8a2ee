// Wheel preintegration against independent truth: the simulator's default trajectories (the integrated
// motion against the spline's, with an error bound from the integration rules and their convergence order),
// Monte Carlo runs (covariance), and bad input and configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "odometry/estimator/config/wheel_factor_config.h"
#include "odometry/estimator/preintegration/wheel_preintegration.h"
#include "tests/unit/estimator/wheel_test_support.h"

namespace uf::estimator {
namespace {

using testing::ErrorBound;
using testing::ErrorsAgainstSpline;
using testing::Generate;
using testing::kMillisecond;
using testing::kRearAxle;
using testing::kSecond;
using testing::kTilted;
using testing::MotionErrors;
using testing::Preintegrate;
using testing::TruthSamples;
using testing::Wheel;

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
  // White noise of fixed densities, as drawn below (the speed-dependent part is the next test's).
  config.suspension_tilt_sigma = config.tilt_per_acceleration = 0.0;
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

TEST(WheelPreintegration, LateralAndVerticalNoiseGrowWithSpeedAndAcceleration) {
  // A turn at 0.25 rad/s while the speed grows from 4 to 8 m/s (2 m/s^2), sampled at 50 Hz. The tilt terms
  // (wheel_factor_config.h) add, per step of mean speed v, 2 v^2 (tau_osc sigma^2 + tau_man (k a)^2) dt to
  // the variance of the lateral (a = v w_z) and the vertical (a = 2 m/s^2, the longitudinal acceleration)
  // position: the difference of the covariances with and without them is that sum exactly in z (the turn is
  // about z) and, in the horizontal block, that sum times cos^2(w dt / 2) (G's position block,
  // -dt (R_k + R_k+1) / 2, rotates the lateral noise and shortens it by that factor).
  constexpr double kAcceleration = 2.0, kYawRate = 0.25;
  std::vector<WheelSample> samples;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.02 * k;
    samples.push_back({k * kSecond / 50, {4.0 + kAcceleration * t, 0, 0}, {0, 0, kYawRate}});
  }
  const WheelFactorConfig with;
  WheelFactorConfig without = with;
  without.suspension_tilt_sigma = without.tilt_per_acceleration = 0.0;
  const Stamp from = kSecond / 10, to = 19 * kSecond / 10;
  const Matrix6d added = Preintegrate(samples, from, to, with).covariance() -
                         Preintegrate(samples, from, to, without).covariance();
  const double oscillation = 2.0 * kSuspensionTiltTime_s * std::pow(with.suspension_tilt_sigma, 2);
  const double manoeuvre = 2.0 * kTiltManoeuvreTime_s * std::pow(with.tilt_per_acceleration, 2);
  double lateral = 0, vertical = 0;
  const double dt = 0.02, shortening = std::pow(std::cos(kYawRate * dt / 2), 2);
  for (int k = 5; k < 95; ++k) {  // the steps of [0.1, 1.9] s
    const double v = 4.0 + kAcceleration * (k + 0.5) * dt;
    lateral += v * v * (oscillation + manoeuvre * std::pow(v * kYawRate, 2)) * dt * shortening;
    vertical += v * v * (oscillation + manoeuvre * kAcceleration * kAcceleration) * dt;
  }
  EXPECT_NEAR(added(2, 2), vertical, 1e-9 * vertical);
  EXPECT_NEAR(added(0, 0) + added(1, 1), lateral, 1e-9 * lateral);
  // At 8 m/s straight, the lateral density is 0.05 m/s/sqrt(Hz) (the header's figure).
  EXPECT_NEAR(std::sqrt(std::pow(with.nonholonomic_velocity_density, 2) + 64 * oscillation), 0.05, 0.005);
  // Only the position block changes: the rotation noise is the same.
  EXPECT_LT((added.bottomRightCorner<3, 3>().norm()), 1e-15);
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
      {&WheelFactorConfig::suspension_tilt_sigma, "lio.wheel.suspension_tilt_sigma"},
      {&WheelFactorConfig::tilt_per_acceleration, "lio.wheel.tilt_per_acceleration"},
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
  // The tilt terms may be switched off.
  config = WheelFactorConfig();
  config.suspension_tilt_sigma = config.tilt_per_acceleration = 0;
  EXPECT_TRUE(config.Validate().ok());
}

}  // namespace
}  // namespace uf::estimator
