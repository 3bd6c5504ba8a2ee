// The online LiDAR-IMU calibration workers (odometry/estimator/calib/) against a simulated rig whose truth is
// known: a body turning about all axes (or only about its vertical), an IMU at 200 Hz with noise and bias,
// a LiDAR odometry at 10 Hz whose frame is turned by R_IL and whose stamps run late.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "odometry/estimator/calib/calibration_consensus.h"
#include "odometry/estimator/calib/online_calibration.h"
#include "odometry/estimator/calib/rate_track.h"
#include "odometry/estimator/calib/rotation_alignment.h"
#include "odometry/estimator/calib/time_offset_search.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// The body's (IMU's) rate: sums of sines about each axis (only about z when yaw_only).
Eigen::Vector3d TrueRate(double t, bool yaw_only) {
  Eigen::Vector3d w;
  w << 0.6 * std::sin(2 * kPi * 0.31 * t) + 0.3 * std::sin(2 * kPi * 0.83 * t + 1.0),
      0.5 * std::sin(2 * kPi * 0.43 * t + 0.5) + 0.2 * std::sin(2 * kPi * 1.1 * t),
      0.7 * std::sin(2 * kPi * 0.23 * t + 2.0) + 0.3 * std::sin(2 * kPi * 0.67 * t + 0.3);
  if (yaw_only) w.head<2>().setZero();
  return w;
}

// Three draws of `normal`, in order.
Eigen::Vector3d Draw(std::mt19937& random, std::normal_distribution<double>& normal) {
  Eigen::Vector3d v;
  v << normal(random), normal(random), normal(random);
  return v;
}

struct Rig {
  SO3 R_imu_lidar = SO3::Exp(Eigen::Vector3d(0.05, -0.08, 0.12));
  Eigen::Vector3d gyro_bias = Eigen::Vector3d(0.004, -0.003, 0.002);
  double lidar_delay_s = 0.0;        // LiDAR stamp = true time + delay
  double gyro_noise = 0.01;          // rad/s per sample
  double lidar_angle_noise = 0.002;  // rad per pose
  bool yaw_only = false;
  double sharp_turn_at_s = -1;  // when >= 0: a yaw burst of up to 3 rad/s (172 deg/s) over 0.6 s from then
};

constexpr double kSharpTurnS = 0.6;

// The rig's rate: TrueRate plus its sharp turn (a sin^2 burst about z).
Eigen::Vector3d RigRate(const Rig& rig, double t) {
  Eigen::Vector3d w = TrueRate(t, rig.yaw_only);
  const double u = (t - rig.sharp_turn_at_s) / kSharpTurnS;
  if (rig.sharp_turn_at_s >= 0 && u > 0 && u < 1) w.z() += 3.0 * std::pow(std::sin(kPi * u), 2);
  return w;
}

struct Streams {
  std::vector<ImuSample> imu;
  std::vector<Stamp> lidar_stamps;
  std::vector<SO3> R_world_lidar;
};

// Integrates the true rate at 2 kHz for `seconds`; samples the IMU at 200 Hz and the LiDAR at 10 Hz.
Streams Simulate(const Rig& rig, double seconds, unsigned seed = 1) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto noise = [&](double sigma) -> Eigen::Vector3d { return Draw(random, normal) * sigma; };
  Streams s;
  const Stamp t0 = 1'700'000'000'000'000'000;
  const int fine = 2000, per_imu = 10, per_lidar = 200;
  SO3 R_world_imu;
  for (int k = 0; k <= static_cast<int>(seconds * fine); ++k) {
    const double t = static_cast<double>(k) / fine;
    const Stamp stamp = t0 + static_cast<Stamp>(std::llround(t * 1e9));
    if (k % per_imu == 0) {
      ImuSample sample;
      sample.stamp = stamp;
      sample.gyro = RigRate(rig, t) + rig.gyro_bias + noise(rig.gyro_noise);
      s.imu.push_back(sample);
    }
    if (k % per_lidar == 0) {
      s.lidar_stamps.push_back(stamp + static_cast<Stamp>(std::llround(rig.lidar_delay_s * 1e9)));
      s.R_world_lidar.push_back(R_world_imu * rig.R_imu_lidar * SO3::Exp(noise(rig.lidar_angle_noise)));
    }
    // Midpoint rule over the fine step.
    R_world_imu = R_world_imu * SO3::Exp(RigRate(rig, t + 0.5 / fine) / fine);
  }
  return s;
}

// The streams as rate tracks on one clock (seconds from the first IMU stamp).
void Tracks(const Streams& s, std::vector<RateSample>& gyro, std::vector<RateSample>& lidar) {
  const Stamp origin = s.imu.front().stamp;
  for (const ImuSample& sample : s.imu) gyro.push_back({ToSeconds(sample.stamp - origin), sample.gyro});
  std::vector<double> t;
  for (Stamp stamp : s.lidar_stamps) t.push_back(ToSeconds(stamp - origin));
  lidar = IntervalRates(t, s.R_world_lidar);
}

TEST(RateTrack, IntervalRatesAndInterpolation) {
  // A constant rate gives itself at every interval middle; Catmull-Rom reproduces a linear ramp exactly.
  const Eigen::Vector3d w(0.1, -0.2, 0.3);
  std::vector<double> t{0.0, 0.1, 0.2, 0.35};
  std::vector<SO3> R;
  for (double ti : t) R.push_back(SO3::Exp(w * ti));
  const std::vector<RateSample> rates = IntervalRates(t, R);
  ASSERT_EQ(rates.size(), 3u);
  EXPECT_NEAR(rates[2].t, 0.275, 1e-12);
  for (const RateSample& r : rates) EXPECT_LT((r.omega - w).norm(), 1e-9);
  std::vector<RateSample> ramp;
  for (int i = 0; i < 6; ++i)
    ramp.push_back(
        {0.1 * i + (i == 3 ? 0.03 : 0.0), Eigen::Vector3d(1, 2, 3) * (0.1 * i + (i == 3 ? 0.03 : 0.0))});
  for (double q : {0.0, 0.05, 0.17, 0.31, 0.42, 0.5}) {
    const std::optional<Eigen::Vector3d> v = InterpolateRate(ramp, q);
    ASSERT_TRUE(v);
    EXPECT_LT((*v - Eigen::Vector3d(1, 2, 3) * q).norm(), 1e-12) << q;
  }
  EXPECT_FALSE(InterpolateRate(ramp, -0.01));
  EXPECT_FALSE(InterpolateRate(ramp, 0.51));
  EXPECT_DOUBLE_EQ(MedianSpacing(ramp), 0.1);
}

TEST(RateTrack, MeanGyroRateIsExactForARateLinearInTime) {
  // About a fixed axis the rotations commute, so the mean rate over [a, b] is the rate at (a + b) / 2.
  // Samples at 200 Hz of w(t) = axis (0.5 + 20 t): holding each sample until the next would come out
  // 20 * 0.0025 = 0.05 rad/s low.
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, 0.0, -0.4).normalized();
  std::vector<RateSample> gyro;
  for (int i = 0; i <= 20; ++i) gyro.push_back({0.005 * i, axis * (0.5 + 20.0 * 0.005 * i)});
  for (const auto& [a, b] : {std::pair{0.0123, 0.0871}, std::pair{0.0, 0.1}, std::pair{0.031, 0.0335}}) {
    const std::optional<Eigen::Vector3d> mean = MeanGyroRate(gyro, a, b);
    ASSERT_TRUE(mean);
    EXPECT_LT((*mean - axis * (0.5 + 20.0 * 0.5 * (a + b))).norm(), 1e-12) << a << " " << b;
  }
  EXPECT_FALSE(MeanGyroRate(gyro, 0.05, 0.2));  // beyond the track
}

TEST(TimeOffsetSearch, RecoversAKnownShiftWithinOneImuSample) {
  for (double delay : {-0.3, -0.02, 0.0, 0.037, 0.25}) {
    Rig rig;
    rig.lidar_delay_s = delay;
    std::vector<RateSample> gyro, lidar;
    Tracks(Simulate(rig, 13.0, 7), gyro, lidar);
    const TimeOffsetEstimate e = SearchTimeOffset(gyro, lidar, TimeOffsetSearchOptions());
    EXPECT_TRUE(e.rejected.empty()) << delay << ": " << e.rejected;
    EXPECT_NEAR(e.shift_s, delay, 0.005) << "one IMU sample is 5 ms";
    EXPECT_GT(e.correlation, 0.9);
    // The fit at the shift recovers the rig too.
    EXPECT_LT((rig.R_imu_lidar.inverse() * e.fit.R_imu_lidar).angle(), 0.5 * kDeg) << delay;
    EXPECT_LT((e.fit.gyro_bias - rig.gyro_bias).norm(), 0.003) << delay;
  }
}

TEST(TimeOffsetSearch, RefusesAStillRigAndTooShortAWindow) {
  std::vector<RateSample> gyro, lidar;
  for (int i = 0; i <= 2600; ++i) gyro.push_back({0.005 * i, Eigen::Vector3d(0.001, 0.0, 0.002)});
  for (int i = 0; i < 130; ++i) lidar.push_back({0.05 + 0.1 * i, Eigen::Vector3d::Zero()});
  EXPECT_NE(SearchTimeOffset(gyro, lidar, {}).rejected.find("too little rotation"), std::string::npos);
  lidar.resize(40);  // 4 s of LiDAR: under the 5 s overlap with the +-0.5 s search
  EXPECT_NE(SearchTimeOffset(gyro, lidar, {}).rejected.find("overlap"), std::string::npos);
}

TEST(RotationAlignment, ProcrustesRecoversARotationAndBiasDespiteOutliers) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  const SO3 R = SO3::Exp(Eigen::Vector3d(0.4, -1.1, 0.7));
  const Eigen::Vector3d bias(0.01, -0.02, 0.005);
  std::vector<RatePair> pairs;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d a = Draw(random, normal);
    Eigen::Vector3d c = R * a + bias + 0.01 * Draw(random, normal);
    if (k % 10 == 0) c += Eigen::Vector3d(2.0, -1.5, 1.0);  // 10 % gross outliers
    pairs.push_back({a, c});
  }
  const RotationFit plain = FitRotation(pairs);
  const RotationFit robust = FitRotationRobust(pairs, 0.05);
  EXPECT_LT((R.inverse() * robust.R_imu_lidar).angle(), 0.1 * kDeg);
  // Huber bounds an outlier's pull at the threshold: 10 % of pairs x 0.05 rad/s moves the bias by ~0.005.
  EXPECT_LT((robust.gyro_bias - bias).norm(), 0.007);
  EXPECT_NEAR(robust.inlier_ratio, 0.9, 0.02);
  EXPECT_LT(robust.rms_residual, 0.03);
  EXPECT_GT((R.inverse() * plain.R_imu_lidar).angle(), (R.inverse() * robust.R_imu_lidar).angle());
  // Rates about one axis only: the excitation says so.
  std::vector<RatePair> single;
  for (int k = 0; k < 100; ++k)
    single.push_back({Eigen::Vector3d(0, 0, std::sin(0.1 * k)), Eigen::Vector3d::Zero()});
  EXPECT_LT(MeasureRotationExcitation(single).ratio, 1e-9);
  EXPECT_GT(MeasureRotationExcitation(pairs).ratio, 0.5);
}

// RotationSigma against Monte Carlo: the spread of the fitted rotation over many noisy draws of independent
// pairs matches the predicted standard deviation.
TEST(RotationAlignment, SigmaPredictsTheSpreadOfTheFit) {
  std::mt19937 random(9);
  std::normal_distribution<double> normal(0.0, 1.0);
  const SO3 R = SO3::Exp(Eigen::Vector3d(0.2, 0.1, -0.3));
  std::vector<Eigen::Vector3d> a;
  for (int k = 0; k < 200; ++k) a.push_back(0.3 * Draw(random, normal));
  double squared_error = 0, predicted = 0;
  const int trials = 300;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<RatePair> pairs;
    for (const Eigen::Vector3d& ak : a) pairs.push_back({ak, R * ak + 0.02 * Draw(random, normal)});
    const RotationFit fit = FitRotation(pairs);
    // The largest axis's variance: with isotropic a the three are equal, so the mean squared angle over
    // the three axes is 3 sigma^2.
    squared_error += (R.inverse() * fit.R_imu_lidar).Log().squaredNorm() / 3.0;
    predicted += RotationSigma(pairs, fit, 1.0) / trials;
  }
  const double measured = std::sqrt(squared_error / trials);
  EXPECT_NEAR(predicted / measured, 1.0, 0.15) << predicted << " vs " << measured;
  // Overlap scales it by its square root; rates about one axis leave it infinite.
  std::vector<RatePair> pairs;
  for (const Eigen::Vector3d& ak : a) pairs.push_back({ak, R * ak});
  pairs[0].imu += Eigen::Vector3d(0.01, 0, 0);
  const RotationFit fit = FitRotation(pairs);
  EXPECT_NEAR(RotationSigma(pairs, fit, 4.0), 2.0 * RotationSigma(pairs, fit, 1.0), 1e-12);
  std::vector<RatePair> single;
  for (int k = 0; k < 50; ++k)
    single.push_back({Eigen::Vector3d(0, 0, 0.01 * k), Eigen::Vector3d(0.001 * (k % 3), 0, 0.01 * k)});
  EXPECT_TRUE(std::isinf(RotationSigma(single, FitRotation(single), 1.0)));
}

TEST(CalibrationConsensus, LocksOnAgreementOnly) {
  const std::vector<double> scattered{0.100, 0.104, 0.098, 0.1011};
  EXPECT_FALSE(OffsetConsensus(scattered, 4, 0.002));
  const std::optional<double> agreed = OffsetConsensus(scattered, 2, 0.002);  // the last two: 0.098, 0.1011
  ASSERT_TRUE(agreed);
  EXPECT_NEAR(*agreed, 0.09955, 1e-12);
  EXPECT_FALSE(OffsetConsensus(scattered, 5, 0.1));  // too few
  const SO3 a = SO3::Exp(Eigen::Vector3d(0.1, 0.2, 0.3));
  std::vector<SO3> rotations{a * SO3::Exp(Eigen::Vector3d(0.001, 0, 0)),
                             a * SO3::Exp(Eigen::Vector3d(-0.001, 0, 0)),
                             a * SO3::Exp(Eigen::Vector3d(0, 0.001, 0))};
  const std::optional<SO3> centre = RotationConsensus(rotations, 3, 0.2 * kDeg);
  ASSERT_TRUE(centre);
  EXPECT_LT((a.inverse() * *centre).angle(), 0.001);
  rotations.push_back(a * SO3::Exp(Eigen::Vector3d(0, 0, 0.01)));  // 0.57 deg away
  EXPECT_FALSE(RotationConsensus(rotations, 3, 0.2 * kDeg));
}

// Feeds the simulated streams in time order, as a run would.
OnlineCalibration Feed(const Streams& s, const OnlineCalibrationOptions& options = {}) {
  OnlineCalibration calibration(options);
  std::size_t l = 0;
  for (const ImuSample& sample : s.imu) {
    while (l < s.lidar_stamps.size() && s.lidar_stamps[l] <= sample.stamp) {
      calibration.AddLidarOrientation(s.lidar_stamps[l], s.R_world_lidar[l]);
      ++l;
    }
    calibration.AddImu(sample);
  }
  return calibration;
}

TEST(OnlineCalibration, LocksTheOffsetAndTheRotationOfAMultiAxisMotion) {
  Rig rig;
  rig.lidar_delay_s = 0.12;
  Streams s = Simulate(rig, 30.0, 11);
  // Bad samples are left out: a NaN gyro, a repeated stamp, a NaN orientation.
  s.imu[500].gyro.x() = std::numeric_limits<double>::quiet_NaN();
  s.imu[900].stamp = s.imu[899].stamp;
  s.R_world_lidar[50] = SO3(Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const OnlineCalibration c = Feed(s);
  ASSERT_TRUE(c.time_offset_locked());
  ASSERT_TRUE(c.rotation_locked());
  EXPECT_NEAR(*c.time_offset_s(), -0.12, 0.002);
  // Within 0.2 deg (the method's figure), with pose noise of 0.11 deg and gyro noise of 0.01 rad/s.
  EXPECT_LT((rig.R_imu_lidar.inverse() * *c.R_imu_lidar()).angle(), 0.2 * kDeg);
  // The offset locked within 20 s of motion (the first solve comes after 6 s), the rotation after its 20 s.
  const Stamp start = s.lidar_stamps.front();
  for (const CalibrationSolve& solve : c.solves()) {
    if (!solve.locked) continue;
    const double seconds = ToSeconds(solve.stamp - start);
    if (solve.worker == CalibrationWorker::kTimeOffset) {
      EXPECT_LT(seconds, 20.0);
    } else {
      EXPECT_GE(seconds, 20.0);
    }
  }
}

// The turning guard: solves fall due every 2 s from 6 s on; the one due at 10 s comes during a sharp turn
// (9.7-10.3 s, up to 172 deg/s on top of the rig's own -44 deg/s about z there) and waits for the first
// pose after it, with one record that says why; the offset still locks on the truth.
TEST(OnlineCalibration, ASolveDueInASharpTurnWaitsForItsEnd) {
  Rig rig;
  rig.lidar_delay_s = 0.05;
  rig.sharp_turn_at_s = 9.7;
  const Streams s = Simulate(rig, 30.0, 3);
  const OnlineCalibration c = Feed(s);
  const Stamp start = s.lidar_stamps.front();
  int waits = 0;
  for (const CalibrationSolve& solve : c.solves()) {
    const double seconds = ToSeconds(solve.stamp - start);  // the pose's true time (the first one's is 0)
    if (solve.reason.find("sharp turn") != std::string::npos) {
      ++waits;
      EXPECT_GT(seconds, rig.sharp_turn_at_s);
      EXPECT_LT(seconds, rig.sharp_turn_at_s + kSharpTurnS);
      continue;
    }
    // The odometry's newest interval is above 60 deg/s for about the middle 0.3 s of the turn.
    EXPECT_FALSE(seconds > rig.sharp_turn_at_s + 0.2 && seconds < rig.sharp_turn_at_s + kSharpTurnS - 0.2)
        << "a solve at " << seconds << " s, inside the turn";
  }
  EXPECT_EQ(waits, 1);
  ASSERT_TRUE(c.time_offset_locked());
  EXPECT_NEAR(*c.time_offset_s(), -0.05, 0.002);
}

// An odometry may release its poses long after the IMU samples of their time (at the end of the data, the
// last window's): the gyro they need is still there. Here the IMU runs 60 s past the LiDAR and comes first.
TEST(OnlineCalibration, PosesThatComeAfterTheImuStillFindTheirGyro) {
  Rig rig;
  rig.lidar_delay_s = -0.07;
  Streams s = Simulate(rig, 90.0, 4);
  s.lidar_stamps.resize(301);  // the first 30 s
  s.R_world_lidar.resize(301);
  OnlineCalibration c;
  for (const ImuSample& sample : s.imu) c.AddImu(sample);
  for (std::size_t l = 0; l < s.lidar_stamps.size(); ++l)
    c.AddLidarOrientation(s.lidar_stamps[l], s.R_world_lidar[l]);
  ASSERT_TRUE(c.time_offset_locked());
  EXPECT_NEAR(*c.time_offset_s(), 0.07, 0.002);
  EXPECT_TRUE(c.rotation_locked());
}

// Bad input: an offset beyond the search range is refused with the reason, never locked; orientations of
// failed registrations (every 10th pose turned by a random 3-10 deg) are outliers the robust fit and its
// checks keep out of the estimate.
TEST(OnlineCalibration, RefusesAnOffsetBeyondTheRangeAndResistsFailedRegistrations) {
  Rig far;
  far.lidar_delay_s = 0.8;  // the search covers +-0.5 s
  const OnlineCalibration beyond = Feed(Simulate(far, 30.0, 6));
  EXPECT_FALSE(beyond.time_offset_locked());
  EXPECT_FALSE(beyond.R_imu_lidar());
  int refused = 0;
  for (const CalibrationSolve& solve : beyond.solves()) {
    EXPECT_FALSE(solve.accepted) << solve.time_offset_s;  // any candidate in +-0.5 s would be wrong
    refused += !solve.reason.empty();
  }
  EXPECT_GT(refused, 5);

  Rig rig;
  rig.lidar_delay_s = 0.04;
  Streams s = Simulate(rig, 30.0, 8);
  std::mt19937 random(2);
  std::uniform_real_distribution<double> angle(3.0 * kDeg, 10.0 * kDeg);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t l = 5; l < s.R_world_lidar.size(); l += 10)
    s.R_world_lidar[l] = s.R_world_lidar[l] * SO3::Exp(Draw(random, normal).normalized() * angle(random));
  const OnlineCalibration c = Feed(s);
  for (const CalibrationSolve& solve : c.solves()) {
    if (solve.accepted && solve.worker == CalibrationWorker::kTimeOffset) {
      EXPECT_NEAR(solve.time_offset_s, -0.04, 0.005);
    }
  }
  ASSERT_TRUE(c.time_offset_s());
  // The rotation worker either keeps the bad pairs out of an accurate estimate or says why it refuses.
  for (const CalibrationSolve& solve : c.solves()) {
    if (solve.worker != CalibrationWorker::kRotation) continue;
    if (solve.accepted) {
      EXPECT_LT((rig.R_imu_lidar.inverse() * solve.R_imu_lidar).angle(), 0.3 * kDeg);
    } else {
      EXPECT_FALSE(solve.reason.empty());
    }
  }
}

TEST(OnlineCalibration, RefusesToLockTheRotationOnASingleAxis) {
  Rig rig;
  rig.yaw_only = true;
  rig.lidar_delay_s = -0.05;
  const OnlineCalibration c = Feed(Simulate(rig, 30.0, 5));
  EXPECT_FALSE(c.rotation_locked());
  EXPECT_FALSE(c.R_imu_lidar());
  int refused = 0;
  for (const CalibrationSolve& solve : c.solves())
    if (solve.worker == CalibrationWorker::kRotation) {
      EXPECT_FALSE(solve.accepted);
      refused += solve.reason.find("too few axes") != std::string::npos;
    }
  EXPECT_GT(refused, 0);
  // The offset needs only the rate's magnitude: it still locks.
  ASSERT_TRUE(c.time_offset_locked());
  EXPECT_NEAR(*c.time_offset_s(), 0.05, 0.003);
}

}  // namespace
}  // namespace uf::estimator
