#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "odometry/sim/imu_model.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf {
namespace {

using Eigen::Vector3d;

constexpr Stamp kSecond = kNanosecondsPerSecond;

// A body at rest at `pose` for 1000 s.
TrajectorySpline Still(const SE3& pose = SE3()) {
  return TrajectorySpline::FromControlPoints(0, 1000 * kSecond, std::vector<SE3>(4, pose));
}

// A body yawing at `rate` rad/s about world z, at the origin (equal increments: exactly constant rate).
TrajectorySpline Spinning(double rate) {
  std::vector<SE3> control;
  for (int i = 0; i < 6; ++i) control.emplace_back(SO3::Exp(Vector3d(0, 0, rate * i)), Vector3d::Zero());
  return TrajectorySpline::FromControlPoints(0, kSecond, control);
}

ImuSimulator MakeSimulator(const TrajectorySpline& trajectory, const ImuNoise& noise, std::uint64_t seed,
                           double rate_hz = 200.0, const SE3& T_body_imu = SE3()) {
  Expected<ImuSimulator> simulator = ImuSimulator::Create(trajectory, T_body_imu, rate_hz, noise, seed);
  EXPECT_TRUE(simulator.ok()) << simulator.error();
  return std::move(simulator).value();
}

TEST(ImuModelTest, AtRestTheAccelerometerReadsGravityUp) {
  const SE3 T_body_imu(SO3::Exp(Vector3d(0.4, -0.3, 1.0)), Vector3d(0.2, 0.1, -0.3));
  const ImuSimulator simulator = MakeSimulator(Still(SE3(SO3::Exp(Vector3d(0, 0, 2.0)), Vector3d(5, 6, 7))),
                                               ImuNoise{}, 1, 200.0, T_body_imu);
  const ImuSample sample = simulator.IdealSample(3 * kSecond);
  // World z up, body yawed only: the imu sees (0, 0, g) of the body frame, rotated into its own axes.
  EXPECT_LT((sample.acc - T_body_imu.rotation().transpose() * Vector3d(0, 0, kStandardGravity)).norm(),
            1e-12);
  EXPECT_LT(sample.gyro.norm(), 1e-12);
}

TEST(ImuModelTest, LeverArmOnATurningBodyFeelsTheCentripetalAcceleration) {
  // Yaw rate w, imu 1 m ahead of the body origin: specific force (-w^2 * 1 m, 0, g), rate (0, 0, w).
  const double w = 0.8;
  const SE3 T_body_imu(SO3(), Vector3d(1.0, 0.0, 0.0));
  const ImuSimulator simulator = MakeSimulator(Spinning(w), ImuNoise{}, 1, 200.0, T_body_imu);
  const ImuSample sample = simulator.IdealSample(1'234'567'890);
  EXPECT_LT((sample.acc - Vector3d(-w * w, 0.0, kStandardGravity)).norm(), 1e-12);
  EXPECT_LT((sample.gyro - Vector3d(0.0, 0.0, w)).norm(), 1e-12);
  // Tangential speed w * 1 m along the body's y axis; at t = 0 the body has yawed by w * 1 s (Spinning's
  // control point 1 sits at the start).
  const ImuKinematics imu = simulator.Kinematics(0);
  EXPECT_LT((imu.velocity_world - SO3::Exp(Vector3d(0, 0, w)) * Vector3d(0.0, w, 0.0)).norm(), 1e-12);
}

TEST(ImuModelTest, StampsFollowTheRateWithoutDrift) {
  // 3 Hz is not a whole number of nanoseconds: each stamp is rounded on its own.
  const ImuSimulator simulator = MakeSimulator(Still(), ImuNoise{}, 1, 3.0);
  const Expected<SimulatedImu> imu = simulator.Generate(10 * kSecond, 20 * kSecond);
  ASSERT_TRUE(imu.ok()) << imu.error();
  ASSERT_EQ(imu->samples.size(), 31u);
  ASSERT_EQ(imu->biases.size(), 31u);
  EXPECT_EQ(imu->samples[1].stamp, 10 * kSecond + 333'333'333);
  EXPECT_EQ(imu->samples[2].stamp, 10 * kSecond + 666'666'667);
  EXPECT_EQ(imu->samples[30].stamp, 20 * kSecond);
  // A very slow rate gives the first sample only.
  const Expected<SimulatedImu> slow = MakeSimulator(Still(), ImuNoise{}, 1, 1e-300).Generate(0, 10 * kSecond);
  ASSERT_TRUE(slow.ok()) << slow.error();
  EXPECT_EQ(slow->samples.size(), 1u);
}

// Per-axis sample standard deviation of a - b over all samples.
Vector3d SampleStd(const std::vector<Vector3d>& values) {
  Vector3d mean = Vector3d::Zero(), square = Vector3d::Zero();
  for (const Vector3d& v : values) mean += v;
  mean /= values.size();
  for (const Vector3d& v : values) square += (v - mean).cwiseAbs2();
  return (square / (values.size() - 1)).cwiseSqrt();
}

TEST(ImuModelTest, WhiteNoiseHasTheDiscreteStandardDeviation) {
  // 10^5 samples at 200 Hz: the sample standard deviation is within ~0.2% (1 / sqrt(2 N)) of
  // density * sqrt(rate); checked to 2%. Biases stay at their initial values.
  ImuNoise noise;
  noise.accel_noise_density = 2.0e-3;
  noise.gyro_noise_density = 1.7e-4;
  noise.initial_accel_bias = Vector3d(0.1, -0.2, 0.3);
  noise.initial_gyro_bias = Vector3d(-0.01, 0.02, 0.005);
  const ImuSimulator simulator = MakeSimulator(Still(), noise, 42);
  const Expected<SimulatedImu> imu = simulator.Generate(0, 500 * kSecond - 1);
  ASSERT_TRUE(imu.ok()) << imu.error();
  ASSERT_EQ(imu->samples.size(), 100'000u);
  std::vector<Vector3d> acc_noise, gyro_noise;
  for (const ImuSample& sample : imu->samples) {
    acc_noise.push_back(sample.acc - Vector3d(0, 0, kStandardGravity) - noise.initial_accel_bias);
    gyro_noise.push_back(sample.gyro - noise.initial_gyro_bias);
  }
  const Vector3d acc_std = SampleStd(acc_noise) / (noise.accel_noise_density * std::sqrt(200.0));
  const Vector3d gyro_std = SampleStd(gyro_noise) / (noise.gyro_noise_density * std::sqrt(200.0));
  test::RecordFigure("accel_std_worst_relative_deviation", (acc_std.array() - 1.0).abs().maxCoeff());
  test::RecordFigure("gyro_std_worst_relative_deviation", (gyro_std.array() - 1.0).abs().maxCoeff());
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(acc_std(axis), 1.0, 0.02) << "axis " << axis;
    EXPECT_NEAR(gyro_std(axis), 1.0, 0.02) << "axis " << axis;
  }
  EXPECT_EQ(imu->biases.back().accel, noise.initial_accel_bias);
  EXPECT_EQ(imu->biases.back().gyro, noise.initial_gyro_bias);
}

TEST(ImuModelTest, BiasRandomWalkVarianceGrowsLinearly) {
  // Var(b(t) - b(0)) = sigma_b^2 t. 400 seeds x 3 axes x (accel, gyro) = 2400 walks per time: the variance
  // estimate is within ~3% (sqrt(2 / 2400)); checked to 12% at t = 1, 4 and 16 s.
  ImuNoise noise;
  noise.accel_bias_random_walk = 3.0e-3;
  noise.gyro_bias_random_walk = 2.0e-5;
  const double rate = 100.0;
  const std::vector<double> times = {1.0, 4.0, 16.0};
  std::vector<double> sum_of_squares(times.size(), 0.0);
  int walks = 0;
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    const Expected<SimulatedImu> imu = MakeSimulator(Still(), noise, seed, rate).Generate(0, 16 * kSecond);
    ASSERT_TRUE(imu.ok()) << imu.error();
    for (std::size_t i = 0; i < times.size(); ++i) {
      const ImuBiases& bias = imu->biases[static_cast<std::size_t>(times[i] * rate)];
      sum_of_squares[i] += (bias.accel / noise.accel_bias_random_walk).squaredNorm() +
                           (bias.gyro / noise.gyro_bias_random_walk).squaredNorm();
    }
    walks += 6;
  }
  for (std::size_t i = 0; i < times.size(); ++i) {
    test::RecordFigure("variance_over_expected_at_" + std::to_string(static_cast<int>(times[i])) + "s",
                       sum_of_squares[i] / walks / times[i]);
    EXPECT_NEAR(sum_of_squares[i] / walks / times[i], 1.0, 0.12) << "t = " << times[i] << " s";
  }
}

TEST(ImuModelTest, SameSeedSameSamplesOtherSeedOthers) {
  ImuNoise noise;
  noise.accel_noise_density = 1e-3;
  noise.gyro_noise_density = 1e-4;
  noise.accel_bias_random_walk = 1e-3;
  noise.gyro_bias_random_walk = 1e-5;
  const TrajectorySpline trajectory = test::RandomSpline(3, 12, kSecond / 10);
  const auto generate = [&](std::uint64_t seed, const ImuNoise& n) {
    return MakeSimulator(trajectory, n, seed).Generate(trajectory.begin(), trajectory.end()).value();
  };
  const SimulatedImu first = generate(7, noise), again = generate(7, noise), other = generate(8, noise);
  ASSERT_EQ(first.samples.size(), again.samples.size());
  ASSERT_EQ(first.samples.size(), other.samples.size());
  int differing = 0;
  for (std::size_t k = 0; k < first.samples.size(); ++k) {
    EXPECT_EQ(first.samples[k].acc, again.samples[k].acc);
    EXPECT_EQ(first.samples[k].gyro, again.samples[k].gyro);
    EXPECT_EQ(first.biases[k].accel, again.biases[k].accel);
    differing +=
        first.samples[k].acc != other.samples[k].acc && first.samples[k].gyro != other.samples[k].gyro;
  }
  EXPECT_EQ(differing, static_cast<int>(first.samples.size()));
  // Switching the accelerometer noise off leaves the gyroscope's draws as they were.
  ImuNoise quiet_accel = noise;
  quiet_accel.accel_noise_density = 0.0;
  const SimulatedImu quiet = generate(7, quiet_accel);
  for (std::size_t k = 0; k < first.samples.size(); ++k)
    EXPECT_EQ(first.samples[k].gyro, quiet.samples[k].gyro);
}

TEST(ImuModelTest, SaturationClampsEachAxis) {
  ImuNoise noise;
  noise.accel_saturation = 4.0;  // below gravity
  noise.gyro_saturation = 0.5;
  const SE3 T_body_imu(SO3(), Vector3d(1.0, 0.0, 0.0));
  const Expected<SimulatedImu> imu =
      MakeSimulator(Spinning(0.8), noise, 1, 200.0, T_body_imu).Generate(0, kSecond);
  ASSERT_TRUE(imu.ok()) << imu.error();
  for (const ImuSample& sample : imu->samples) {
    EXPECT_NEAR(sample.acc.x(), -0.64, 1e-12);  // inside the range: untouched
    EXPECT_EQ(sample.acc.z(), 4.0);
    EXPECT_EQ(sample.gyro.z(), 0.5);
  }
}

// The error message of a failing Create, or "" when it succeeds.
std::string CreateError(double rate_hz, const ImuNoise& noise, double gravity = kStandardGravity) {
  const Expected<ImuSimulator> simulator = ImuSimulator::Create(Still(), SE3(), rate_hz, noise, 1, gravity);
  return simulator.ok() ? "" : simulator.error();
}

TEST(ImuModelTest, BadInputIsAnErrorNamingTheValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(CreateError(200.0, ImuNoise{}), "");
  EXPECT_EQ(CreateError(0.0, ImuNoise{}),
            "imu rate must be > 0 Hz and at most 1e9 Hz (one sample per ns), got 0");
  EXPECT_EQ(CreateError(-100.0, ImuNoise{}),
            "imu rate must be > 0 Hz and at most 1e9 Hz (one sample per ns), got -100");
  EXPECT_EQ(CreateError(nan, ImuNoise{}),
            "imu rate must be > 0 Hz and at most 1e9 Hz (one sample per ns), got nan");
  EXPECT_EQ(CreateError(2e9, ImuNoise{}),
            "imu rate must be > 0 Hz and at most 1e9 Hz (one sample per ns), got 2e+09");
  ImuNoise negative;
  negative.gyro_noise_density = -1e-4;
  EXPECT_EQ(CreateError(200.0, negative), "imu gyro_noise_density must be finite and >= 0, got -0.0001");
  ImuNoise infinite;
  infinite.accel_bias_random_walk = std::numeric_limits<double>::infinity();
  EXPECT_EQ(CreateError(200.0, infinite), "imu accel_bias_random_walk must be finite and >= 0, got inf");
  ImuNoise bad_saturation;
  bad_saturation.accel_saturation = -1.0;
  EXPECT_EQ(CreateError(200.0, bad_saturation), "imu accel_saturation must be finite and >= 0, got -1");
  ImuNoise bad_bias;
  bad_bias.initial_gyro_bias.y() = nan;
  EXPECT_EQ(CreateError(200.0, bad_bias), "imu initial biases must be finite");
  EXPECT_EQ(CreateError(200.0, ImuNoise{}, nan), "imu gravity must be finite and >= 0, got nan");

  const ImuSimulator simulator = MakeSimulator(Still(), ImuNoise{}, 1);
  EXPECT_EQ(simulator.Generate(2 * kSecond, kSecond).error(),
            "imu simulation interval is empty: begin 2.000000000 s is after end 1.000000000 s");
  EXPECT_EQ(simulator.Generate(-1, kSecond).error(),
            "imu simulation interval [-0.000000001, 1.000000000] s is not inside the trajectory "
            "[0.000000000, 1000.000000000] s");
  EXPECT_NE(
      MakeSimulator(Still(), ImuNoise{}, 1, 1e9).Generate(0, 900 * kSecond).error().find("more than 1e8"),
      std::string::npos);
}

}  // namespace
}  // namespace uf
