// IMU preintegration against independent truth: the simulator's spline states (deltas, Predict, midpoint
// convergence order), numeric re-integration (bias Jacobians, first-order update), Monte Carlo runs of the
// noisy simulator (covariance), and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "tests/unit/estimator/imu_test_support.h"

namespace uf::estimator {
namespace {

using testing::kSecond;
using testing::MovingImu;
using testing::Samples;
using testing::TrueState;

using testing::kAccelBias;
using testing::kGyroBias;

struct DeltaErrors {
  double rotation, velocity, position;  // rad, m/s, m
};

// Preintegration of ideal samples (plus constant biases) against the true deltas between the spline states:
//   dR = R_i^T R_j,  dv = R_i^T (v_j - v_i - g T),  dp = R_i^T (p_j - p_i - v_i T - g T^2 / 2).
DeltaErrors ErrorsAgainstTruth(double rate_hz, Stamp t_i, Stamp t_j) {
  ImuNoise noise;
  noise.initial_accel_bias = kAccelBias;
  noise.initial_gyro_bias = kGyroBias;
  const ImuSimulator imu = MovingImu(rate_hz, noise);
  const auto pre = ImuPreintegration::Between(Samples(imu, 0, 4 * kSecond), t_i, t_j, kAccelBias, kGyroBias,
                                              ImuNoiseParams());
  EXPECT_TRUE(pre.ok()) << pre.error();
  const NavState i = TrueState(imu, t_i), j = TrueState(imu, t_j);
  const Eigen::Matrix3d& R_i = i.T_world_imu.rotation();
  const double T = ToSeconds(t_j - t_i);
  const Eigen::Vector3d g(0, 0, -kStandardGravity);
  const SO3 dR(R_i.transpose() * j.T_world_imu.rotation());
  const Eigen::Vector3d dv = R_i.transpose() * (j.velocity - i.velocity - g * T);
  const Eigen::Vector3d dp = R_i.transpose() * (j.T_world_imu.translation() - i.T_world_imu.translation() -
                                                i.velocity * T - 0.5 * g * T * T);
  EXPECT_EQ(pre->sum_dt(), t_j - t_i);
  return {(dR.inverse() * pre->delta_R()).Log().norm(), (pre->delta_v() - dv).norm(),
          (pre->delta_p() - dp).norm()};
}

TEST(ImuPreintegration, MatchesSplineDeltasOverShortAndLongIntervals) {
  // 200 Hz; t_i on a sample, t_j between samples (interpolated boundary) for the 1 s interval. Measured:
  // 0.1 s: 2.5e-7 rad, 1.5e-7 m/s, 3.1e-7 m; 1 s: 1.6e-6 rad, 7.8e-6 m/s, 4.2e-6 m.
  const DeltaErrors short_interval = ErrorsAgainstTruth(200.0, kSecond / 2, kSecond / 2 + kSecond / 10);
  EXPECT_LT(short_interval.rotation, 1e-6);
  EXPECT_LT(short_interval.velocity, 1e-6);
  EXPECT_LT(short_interval.position, 1e-6);
  const DeltaErrors long_interval = ErrorsAgainstTruth(200.0, kSecond / 2, 3 * kSecond / 2 + 1'234'567);
  EXPECT_LT(long_interval.rotation, 5e-6);
  EXPECT_LT(long_interval.velocity, 3e-5);
  EXPECT_LT(long_interval.position, 2e-5);
  std::cout << "200 Hz errors, 0.1 s: " << short_interval.rotation << " rad, " << short_interval.velocity
            << " m/s, " << short_interval.position << " m; 1 s: " << long_interval.rotation << " rad, "
            << long_interval.velocity << " m/s, " << long_interval.position << " m\n";
}

TEST(ImuPreintegration, MidpointErrorShrinksFourfoldWhenRateDoubles) {
  // Second-order convergence of the midpoint rule: the error ratio between 200 Hz and 400 Hz is ~4.
  const DeltaErrors coarse = ErrorsAgainstTruth(200.0, kSecond / 2, 3 * kSecond / 2);
  const DeltaErrors fine = ErrorsAgainstTruth(400.0, kSecond / 2, 3 * kSecond / 2);
  for (const auto& [a, b] :
       {std::pair{coarse.rotation, fine.rotation}, std::pair{coarse.velocity, fine.velocity},
        std::pair{coarse.position, fine.position}}) {
    EXPECT_GT(a / b, 3.5);
    EXPECT_LT(a / b, 4.5);
  }
}

TEST(ImuPreintegration, PredictReproducesTheTrueState) {
  ImuNoise noise;
  noise.initial_accel_bias = kAccelBias;
  noise.initial_gyro_bias = kGyroBias;
  const ImuSimulator imu = MovingImu(1000.0, noise);
  const Stamp t_i = kSecond, t_j = 2 * kSecond;
  // Linearized away from the true biases: Predict corrects with the biases of state i.
  const auto pre = ImuPreintegration::Between(Samples(imu, 0, 3 * kSecond), t_i, t_j, kAccelBias * 0.7,
                                              kGyroBias * 0.8, ImuNoiseParams());
  ASSERT_TRUE(pre.ok()) << pre.error();
  const NavState predicted = pre->Predict(TrueState(imu, t_i, kAccelBias, kGyroBias));
  const NavState truth = TrueState(imu, t_j, kAccelBias, kGyroBias);
  EXPECT_EQ(predicted.stamp, t_j);
  EXPECT_LT((truth.T_world_imu.so3().inverse() * predicted.T_world_imu.so3()).Log().norm(), 1e-5);
  EXPECT_LT((truth.velocity - predicted.velocity).norm(), 1e-4);
  EXPECT_LT((truth.T_world_imu.translation() - predicted.T_world_imu.translation()).norm(), 1e-4);
  EXPECT_EQ(predicted.accel_bias, kAccelBias);
  EXPECT_EQ(predicted.gyro_bias, kGyroBias);
}

// [Log(dR), dv, dp] of a re-integration at biases (ba, bg), relative to the reference deltas.
Eigen::Matrix<double, 9, 1> DeltasAt(ImuPreintegration pre, const ImuPreintegration& reference,
                                     const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) {
  pre.Repropagate(ba, bg);
  Eigen::Matrix<double, 9, 1> d;
  d << (reference.delta_R().inverse() * pre.delta_R()).Log(), pre.delta_v(), pre.delta_p();
  return d;
}

TEST(ImuPreintegration, BiasJacobiansMatchNumericReintegration) {
  const ImuSimulator imu = MovingImu(200.0);
  const auto pre = ImuPreintegration::Between(Samples(imu, 0, 3 * kSecond), kSecond / 2, 3 * kSecond / 2,
                                              kAccelBias, kGyroBias, ImuNoiseParams());
  ASSERT_TRUE(pre.ok());
  // Columns of d[dtheta, dv, dp]/d[ba, bg] by central differences of full re-integrations.
  Eigen::Matrix<double, 9, 6> numeric;
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 1e-3 : 1e-4;
    Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
    step(k) = h;
    const auto plus = DeltasAt(*pre, *pre, kAccelBias + step.head<3>(), kGyroBias + step.tail<3>());
    const auto minus = DeltasAt(*pre, *pre, kAccelBias - step.head<3>(), kGyroBias - step.tail<3>());
    numeric.col(k) = (plus - minus) / (2 * h);
  }
  const Eigen::Matrix<double, 9, 6> analytic = pre->bias_jacobian();
  // dR/dba is zero in both; every other block is compared relative to its size.
  EXPECT_LT((numeric.block<3, 3>(0, 0).norm()), 1e-9);
  EXPECT_EQ((analytic.block<3, 3>(0, 0).norm()), 0.0);
  for (const auto& [row, col] :
       {std::pair{0, 3}, std::pair{3, 0}, std::pair{3, 3}, std::pair{6, 0}, std::pair{6, 3}}) {
    const Eigen::Matrix3d a = analytic.block<3, 3>(row, col), n = numeric.block<3, 3>(row, col);
    EXPECT_LT((a - n).norm(), 1e-6 * n.norm()) << "block " << row << ", " << col << "\n" << a << "\n" << n;
  }
  EXPECT_EQ(pre->dv_dbg(), (analytic.block<3, 3>(3, 3)));
  EXPECT_EQ(pre->dp_dba(), (analytic.block<3, 3>(6, 0)));
}

TEST(ImuPreintegration, FirstOrderUpdateMatchesReintegrationToSecondOrder) {
  const ImuSimulator imu = MovingImu(200.0);
  const auto pre = ImuPreintegration::Between(Samples(imu, 0, 3 * kSecond), kSecond / 2, 3 * kSecond / 2,
                                              kAccelBias, kGyroBias, ImuNoiseParams());
  ASSERT_TRUE(pre.ok());
  for (const double scale : {1.0, 0.5}) {
    const Eigen::Vector3d ba = kAccelBias + scale * Eigen::Vector3d(0.05, -0.04, 0.03);
    const Eigen::Vector3d bg = kGyroBias + scale * Eigen::Vector3d(-0.004, 0.005, 0.003);
    ImuPreintegration exact = *pre;
    exact.Repropagate(ba, bg);
    const double rotation = (exact.delta_R().inverse() * pre->CorrectedDeltaR(bg)).Log().norm();
    const double velocity = (exact.delta_v() - pre->CorrectedDeltaV(ba, bg)).norm();
    const double position = (exact.delta_p() - pre->CorrectedDeltaP(ba, bg)).norm();
    // Without the update the deltas are off by ~|db| T (~1e-2); with it only by the second-order term.
    const double uncorrected_velocity = (exact.delta_v() - pre->delta_v()).norm();
    EXPECT_GT(uncorrected_velocity, 1e-2 * scale);
    // Measured at scale 1 (|db_a| = 0.07, |db_g| = 0.007, T = 1 s): 1.6e-6 rad, 2.1e-4 m/s, and 4x less
    // at scale 1/2.
    EXPECT_LT(rotation, 2.5e-6 * scale * scale);
    EXPECT_LT(velocity, 3e-4 * scale * scale);
    EXPECT_LT(position, 1e-4 * scale * scale);
    std::cout << "first-order update error at scale " << scale << ": " << rotation << " rad, " << velocity
              << " m/s, " << position << " m\n";
  }
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  // 1000 noisy runs (white noise and bias random walk at the default densities, different seeds) against a
  // noise-free run (the truth to ~1e-6): the IMU factor's residual at the true states,
  // e = [Log(dR^T dR_ref), dv_ref - dv, dp_ref - dp, ba_j - ba_i, bg_j - bg_i].
  const ImuNoiseParams params;
  ImuNoise noise;
  noise.accel_noise_density = params.accel_noise_density;
  noise.gyro_noise_density = params.gyro_noise_density;
  noise.accel_bias_random_walk = params.accel_bias_random_walk;
  noise.gyro_bias_random_walk = params.gyro_bias_random_walk;
  const Stamp t_i = kSecond / 2, t_j = 3 * kSecond / 2;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const auto reference =
      ImuPreintegration::Between(Samples(MovingImu(200.0), t_i, t_j), t_i, t_j, zero, zero, params);
  ASSERT_TRUE(reference.ok());
  constexpr int kRuns = 1000;
  Eigen::Matrix<double, 15, Eigen::Dynamic> errors(15, kRuns);
  const TrajectorySpline trajectory = testing::MovingTrajectory();
  const ImuSimulator noisy_imu = MovingImu(200.0, noise, 0);
  for (int run = 0; run < kRuns; ++run) {
    auto imu = ImuSimulator::Create(trajectory, noisy_imu.T_body_imu(), 200.0, noise, 1000 + run);
    ASSERT_TRUE(imu.ok());
    const auto simulated = imu->Generate(t_i, t_j);
    ASSERT_TRUE(simulated.ok());
    const auto pre = ImuPreintegration::Between(simulated->samples, t_i, t_j, zero, zero, params);
    ASSERT_TRUE(pre.ok());
    errors.col(run) << (pre->delta_R().inverse() * reference->delta_R()).Log(),
        reference->delta_v() - pre->delta_v(), reference->delta_p() - pre->delta_p(),
        simulated->biases.back().accel - simulated->biases.front().accel,
        simulated->biases.back().gyro - simulated->biases.front().gyro;
  }
  const Eigen::Matrix<double, 15, 1> mean = errors.rowwise().mean();
  const Eigen::MatrixXd centred = errors.colwise() - mean;
  const Matrix15d sample = centred * centred.transpose() / (kRuns - 1);
  const Matrix15d& propagated = reference->covariance();
  const Eigen::Matrix<double, 15, 1> ratio = sample.diagonal().cwiseQuotient(propagated.diagonal());
  for (int k = 0; k < 15; ++k) EXPECT_NEAR(ratio(k), 1.0, 0.15) << "diagonal " << k;
  std::cout << "Monte Carlo / propagated variance: " << ratio.transpose() << "\n";
  // The strongest correlations (dv with dp, dp with dba) agree too.
  for (const auto& [r, c] : {std::pair{3, 6}, std::pair{4, 7}, std::pair{6, 9}, std::pair{3, 9}}) {
    const double sample_corr = sample(r, c) / std::sqrt(sample(r, r) * sample(c, c));
    const double propagated_corr = propagated(r, c) / std::sqrt(propagated(r, r) * propagated(c, c));
    EXPECT_NEAR(sample_corr, propagated_corr, 0.1) << r << ", " << c;
  }
}

TEST(ImuPreintegration, RejectsBadStepsAndKeepsItsState) {
  ImuPreintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), ImuNoiseParams());
  ImuSample a, b;
  a.stamp = 100;
  b.stamp = 5'000'100;
  a.acc = b.acc = Eigen::Vector3d(0, 0, kStandardGravity);
  ASSERT_TRUE(pre.Integrate(a, b).ok());
  const Eigen::Vector3d dv = pre.delta_v();
  ImuSample c = b;
  c.stamp = b.stamp;
  EXPECT_NE(pre.Integrate(b, c).message().find("stamps must increase"), std::string::npos);  // dt = 0
  c.stamp = a.stamp;
  EXPECT_FALSE(pre.Integrate(b, c).ok());  // dt < 0
  c.stamp = b.stamp + 5'000'000;
  c.gyro.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(pre.Integrate(b, c).message().find("non-finite"), std::string::npos);
  c.gyro.y() = 0;
  c.acc.x() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(pre.Integrate(b, c).ok());
  EXPECT_EQ(pre.num_steps(), 1);
  EXPECT_EQ(pre.sum_dt(), 5'000'000);
  EXPECT_EQ(pre.delta_v(), dv);
  EXPECT_TRUE(pre.covariance().allFinite());
}

TEST(ImuPreintegration, BetweenRejectsBadIntervals) {
  const std::vector<ImuSample> samples = Samples(MovingImu(200.0), kSecond, 2 * kSecond);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const ImuNoiseParams params;
  EXPECT_FALSE(ImuPreintegration::Between(samples, kSecond + 10, kSecond + 10, zero, zero, params).ok());
  EXPECT_FALSE(ImuPreintegration::Between(samples, kSecond / 2, kSecond * 3 / 2, zero, zero, params).ok());
  EXPECT_FALSE(ImuPreintegration::Between(samples, kSecond, kSecond * 3, zero, zero, params).ok());
  EXPECT_FALSE(ImuPreintegration::Between({}, kSecond, kSecond * 2, zero, zero, params).ok());
  std::vector<ImuSample> with_nan = samples;
  with_nan[50].acc.z() = std::numeric_limits<double>::quiet_NaN();
  const auto failed = ImuPreintegration::Between(with_nan, kSecond, 2 * kSecond, zero, zero, params);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().find("non-finite"), std::string::npos);
  // Exactly the covered interval is fine and uses the 200 samples as they are.
  const auto full = ImuPreintegration::Between(samples, kSecond, 2 * kSecond, zero, zero, params);
  ASSERT_TRUE(full.ok());
  EXPECT_EQ(full->num_steps(), 200);
}

// Clipped readings (imu_preintegration.h), hand-computed on one 5 ms step turning about x: both ends at the
// gyro's full scale add (kClippedExcess range)^2 dt^2 to the rotation's x variance (Jr leaves its own axis
// as it is) and nothing to the biases; one end at it, a quarter of that; readings under it, nothing. An
// accelerometer clipped on z adds (kClippedExcess range)^2 dt^2 to the velocity's z variance.
TEST(ImuPreintegration, ClippedReadingsAddTheirExcessAsNoise) {
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const double dt = 0.005, range = 0.25;
  const auto step_covariance = [&](double begin_rate, double end_rate, const ImuNoiseParams& params,
                                   int* clipped = nullptr) {
    const ImuSample a{
        .stamp = 0, .acc = Eigen::Vector3d(0, 0, 9.81), .gyro = Eigen::Vector3d(begin_rate, 0, 0)};
    const ImuSample b{.stamp = 5'000'000, .acc = a.acc, .gyro = Eigen::Vector3d(end_rate, 0, 0)};
    ImuPreintegration pre(zero, zero, params);
    EXPECT_TRUE(pre.Integrate(a, b).ok());
    if (clipped) *clipped = pre.clipped_steps();
    return pre.covariance();
  };
  ImuNoiseParams told;
  told.gyro_range = range;
  const ImuNoiseParams untold;
  const double excess2 = std::pow(kClippedExcess * range, 2) * dt * dt;
  int clipped = -1;
  const Matrix15d both =
      step_covariance(range, -range, told, &clipped) - step_covariance(range, -range, untold);
  EXPECT_EQ(clipped, 1);
  EXPECT_NEAR(both(kImuRotation, kImuRotation), excess2, 1e-12 * excess2);
  const Eigen::Matrix3d rotation = both.block<3, 3>(kImuRotation, kImuRotation);
  EXPECT_NEAR(rotation.norm(), excess2, 1e-9 * excess2);
  const Eigen::Matrix<double, 6, 6> biases = both.bottomRightCorner<6, 6>();
  EXPECT_EQ(biases.norm(), 0.0);
  const Matrix15d one = step_covariance(0.1, range, told, &clipped) - step_covariance(0.1, range, untold);
  EXPECT_EQ(clipped, 1);
  EXPECT_NEAR(one(kImuRotation, kImuRotation), excess2 / 4, 1e-9 * excess2);
  const Matrix15d under = step_covariance(0.2, 0.24, told, &clipped) - step_covariance(0.2, 0.24, untold);
  EXPECT_EQ(clipped, 0);
  EXPECT_EQ(under.norm(), 0.0);

  ImuNoiseParams accel_told;
  accel_told.accel_range = 9.0;  // below the 9.81 m/s^2 read on z
  const Matrix15d accel = step_covariance(0, 0, accel_told, &clipped) - step_covariance(0, 0, untold);
  EXPECT_EQ(clipped, 1);
  const double accel_excess2 = std::pow(kClippedExcess * 9.0, 2) * dt * dt;
  EXPECT_NEAR(accel(kImuVelocity + 2, kImuVelocity + 2), accel_excess2, 1e-9 * accel_excess2);
  EXPECT_NEAR(accel(kImuRotation, kImuRotation), 0.0, 1e-18);
}

TEST(ImuNoiseParams, ValidationNamesFieldAndValue) {
  EXPECT_TRUE(ValidateImuNoiseParams(ImuNoiseParams()).ok());
  ImuNoiseParams params;
  params.gyro_noise_density = -1.0;
  EXPECT_NE(ValidateImuNoiseParams(params).message().find("imu.gyro_noise_density"), std::string::npos);
  EXPECT_NE(ValidateImuNoiseParams(params).message().find("-1"), std::string::npos);
  params = ImuNoiseParams();
  params.gravity = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ValidateImuNoiseParams(params).message().find("imu.gravity"), std::string::npos);
  params = ImuNoiseParams();
  params.max_gyro_bias_change = 0.0;
  EXPECT_NE(ValidateImuNoiseParams(params).message().find("imu.max_gyro_bias_change"), std::string::npos);
  params = ImuNoiseParams();
  params.gyro_range = -0.5;
  EXPECT_NE(
      ValidateImuNoiseParams(params).message().find("imu.gyro_range: must be finite and >= 0, got -0.5"),
      std::string::npos);
  params = ImuNoiseParams();
  params.accel_range = std::numeric_limits<double>::infinity();
  EXPECT_NE(ValidateImuNoiseParams(params).message().find("imu.accel_range"), std::string::npos);
}

}  // namespace
}  // namespace uf::estimator
