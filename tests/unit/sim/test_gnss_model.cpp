#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "odometry/sim/gnss_model.h"
#include "tests/unit/sim/sim_test_support.h"

namespace uf::sim {
namespace {

using Eigen::Vector3d;

constexpr Stamp kSecond = kNanosecondsPerSecond;
const GeodeticOrigin kOrigin{48.137, 11.575, 520.0};

// The smooth 3D drive of the test support, 40 s from t = 0.
const TrajectorySpline& Smooth() {
  static const TrajectorySpline spline =
      TrajectorySpline::FitPoses(test::SampleSmoothTrajectory(0, 40.0, 100.0), 50'000'000).value();
  return spline;
}

// At rest at the origin for 30000 s.
TrajectorySpline Still() {
  return TrajectorySpline::FromControlPoints(0, 30000 * kSecond, std::vector<SE3>(4, SE3()));
}

GnssConfig NoiseFree() {
  GnssConfig config;
  config.rtk_fixed = config.rtk_float = config.single = GnssNoise{};
  return config;
}

SimulatedGnss Simulate(const TrajectorySpline& trajectory, const GnssConfig& config, Stamp begin, Stamp end,
                       std::uint64_t seed = 1, const SE3& T_body_antenna = SE3()) {
  Expected<GnssSimulator> simulator =
      GnssSimulator::Create(trajectory, T_body_antenna, config, kOrigin, seed);
  EXPECT_TRUE(simulator.ok()) << simulator.error();
  Expected<SimulatedGnss> gnss = simulator->Generate(begin, end);
  EXPECT_TRUE(gnss.ok()) << gnss.error();
  return std::move(gnss).value();
}

// The measured ENU position of a fix.
Vector3d FixEnu(const GnssFix& fix) {
  return EnuFromGeodetic(kOrigin, Vector3d(fix.latitude_deg, fix.longitude_deg, fix.altitude_m));
}

// Measured minus true ENU of every fix.
std::vector<Vector3d> Errors(const SimulatedGnss& gnss) {
  std::vector<Vector3d> errors;
  for (std::size_t i = 0; i < gnss.fixes.size(); ++i)
    errors.push_back(FixEnu(gnss.fixes[i]) - gnss.true_enu[i]);
  return errors;
}

// Sample standard deviation of one axis.
double AxisStd(const std::vector<Vector3d>& values, int axis) {
  double sum = 0, square = 0;
  for (const Vector3d& v : values) sum += v(axis), square += v(axis) * v(axis);
  const double n = static_cast<double>(values.size());
  return std::sqrt(square / n - (sum / n) * (sum / n));
}

// Sample autocorrelation at `lag` samples, pooled over the three axes (each normalised by its variance).
double Autocorrelation(const std::vector<Vector3d>& values, std::size_t lag) {
  double total = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double mean = 0;
    for (const Vector3d& v : values) mean += v(axis);
    mean /= static_cast<double>(values.size());
    double covariance = 0, variance = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      variance += (values[i](axis) - mean) * (values[i](axis) - mean);
      if (i + lag < values.size()) covariance += (values[i](axis) - mean) * (values[i + lag](axis) - mean);
    }
    total += covariance / variance;
  }
  return total / 3.0;
}

TEST(GnssModelTest, NoiseFreeFixesAreTheTrueAntennaPosition) {
  const SE3 T_body_antenna(SO3::Exp(Vector3d(0.3, 0.1, -0.2)), Vector3d(-0.4, 0.2, 1.3));
  const SimulatedGnss gnss = Simulate(Smooth(), NoiseFree(), 2 * kSecond, 38 * kSecond, 1, T_body_antenna);
  ASSERT_EQ(gnss.fixes.size(), 36u * 5u + 1u);
  ASSERT_EQ(gnss.true_enu.size(), gnss.fixes.size());
  EXPECT_EQ(gnss.fixes[1].stamp, 2 * kSecond + 200'000'000);
  for (std::size_t i = 0; i < gnss.fixes.size(); ++i) {
    const GnssFix& fix = gnss.fixes[i];
    // p_enu = p_body + R_world_body r, with world = ENU at the origin.
    const SE3 T_world_body = Smooth().Evaluate(fix.stamp).T_world_body;
    const Vector3d antenna = T_world_body.translation() + T_world_body.rotation() * Vector3d(-0.4, 0.2, 1.3);
    EXPECT_LT((gnss.true_enu[i] - antenna).norm(), 1e-12) << i;
    EXPECT_LT((FixEnu(fix) - antenna).norm(), 1e-6) << i;
    EXPECT_EQ(fix.status, GnssFixStatus::kFix);
    EXPECT_EQ(fix.covariance_enu, Eigen::Matrix3d::Zero());
  }
}

TEST(GnssModelTest, EachQualityHasItsNominalNoiseAndCorrelationTime) {
  const GnssConfig defaults;
  for (const GnssQuality quality : {GnssQuality::kRtkFixed, GnssQuality::kRtkFloat, GnssQuality::kSingle}) {
    GnssConfig config;
    config.rate_hz = 1.0;
    config.quality = quality;
    const GnssNoise& noise = defaults.Noise(quality);
    const SimulatedGnss gnss = Simulate(Still(), config, 0, 20000 * kSecond, 5);
    ASSERT_EQ(gnss.fixes.size(), 20001u);
    const std::vector<Vector3d> errors = Errors(gnss);
    const Vector3d nominal(noise.horizontal_std_m, noise.horizontal_std_m, noise.vertical_std_m);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(AxisStd(errors, axis) / nominal(axis), 1.0, 0.1)
          << static_cast<int>(quality) << " " << axis;
    }
    // The Gauss-Markov process has autocorrelation exp(-lag / tau): estimate tau from lag 1 s.
    const double tau = -1.0 / std::log(Autocorrelation(errors, 1));
    test::RecordFigure("gnss_tau_ratio_" + std::to_string(static_cast<int>(quality)),
                       tau / noise.correlation_time_s);
    EXPECT_NEAR(tau / noise.correlation_time_s, 1.0, 0.15) << static_cast<int>(quality);
    EXPECT_EQ(gnss.fixes[0].covariance_enu, Eigen::Matrix3d(nominal.cwiseAbs2().asDiagonal()));
    EXPECT_EQ(gnss.fixes[0].status, ToFixStatus(quality));
  }
}

TEST(GnssModelTest, SinglePointFixesWanderAndWhiteNoiseDoesNot) {
  GnssConfig config;
  config.rate_hz = 1.0;
  const std::vector<Vector3d> wandering = Errors(Simulate(Still(), config, 0, 20000 * kSecond, 9));
  // One correlation time (30 s) apart the errors are still correlated by exp(-1).
  EXPECT_NEAR(Autocorrelation(wandering, 30), std::exp(-1.0), 0.08);
  EXPECT_GT(Autocorrelation(wandering, 1), 0.95);
  config.single.correlation_time_s = 0.0;
  const std::vector<Vector3d> white = Errors(Simulate(Still(), config, 0, 5000 * kSecond, 9));
  EXPECT_NEAR(Autocorrelation(white, 1), 0.0, 0.05);
  EXPECT_NEAR(AxisStd(white, 0) / 1.5, 1.0, 0.05);
  EXPECT_NEAR(AxisStd(white, 2) / 3.0, 1.0, 0.05);
}

TEST(GnssModelTest, OutagesRemoveTheFixesInsideOnly) {
  GnssConfig config;
  config.outages = {TimeWindow{10 * kSecond, 20 * kSecond}, TimeWindow{30 * kSecond, 31 * kSecond}};
  const SimulatedGnss with = Simulate(Smooth(), config, 0, 40 * kSecond, 3);
  const SimulatedGnss without = Simulate(Smooth(), GnssConfig{}, 0, 40 * kSecond, 3);
  ASSERT_EQ(without.fixes.size(), 201u);
  ASSERT_EQ(with.fixes.size(), 201u - 50u - 5u);
  std::size_t j = 0;
  for (const GnssFix& fix : without.fixes) {
    const bool dark = (fix.stamp >= 10 * kSecond && fix.stamp < 20 * kSecond) ||
                      (fix.stamp >= 30 * kSecond && fix.stamp < 31 * kSecond);
    if (dark) continue;
    ASSERT_LT(j, with.fixes.size());
    // The same fixes otherwise: the error processes run on through the outage.
    EXPECT_EQ(with.fixes[j].stamp, fix.stamp);
    EXPECT_EQ(with.fixes[j].latitude_deg, fix.latitude_deg);
    EXPECT_EQ(with.fixes[j].altitude_m, fix.altitude_m);
    ++j;
  }
  EXPECT_EQ(j, with.fixes.size());
}

TEST(GnssModelTest, MultipathOffsetsAreAddedInsideTheirWindows) {
  GnssConfig config = NoiseFree();
  config.multipath = {{TimeWindow{10 * kSecond, 20 * kSecond}, Vector3d(3.0, -2.0, 5.0)},
                      {TimeWindow{15 * kSecond, 25 * kSecond}, Vector3d(0.5, 0.5, 0.0)}};
  const SimulatedGnss gnss = Simulate(Smooth(), config, 0, 30 * kSecond);
  for (std::size_t i = 0; i < gnss.fixes.size(); ++i) {
    const Stamp t = gnss.fixes[i].stamp;
    Vector3d expected = Vector3d::Zero();
    if (t >= 10 * kSecond && t < 20 * kSecond) expected += Vector3d(3.0, -2.0, 5.0);
    if (t >= 15 * kSecond && t < 25 * kSecond) expected += Vector3d(0.5, 0.5, 0.0);
    EXPECT_LT((FixEnu(gnss.fixes[i]) - gnss.true_enu[i] - expected).norm(), 1e-6) << t;
  }
}

TEST(GnssModelTest, StatusAndCovarianceFollowTheQualityChanges) {
  GnssConfig config;
  config.quality_changes = {{TimeWindow{10 * kSecond, 20 * kSecond}, GnssQuality::kRtkFixed},
                            {TimeWindow{15 * kSecond, 18 * kSecond}, GnssQuality::kRtkFloat}};
  const SimulatedGnss gnss = Simulate(Smooth(), config, 0, 30 * kSecond, 4);
  const std::vector<Vector3d> errors = Errors(gnss);
  int counts[3] = {0, 0, 0};
  for (std::size_t i = 0; i < gnss.fixes.size(); ++i) {
    const Stamp t = gnss.fixes[i].stamp;
    GnssFixStatus expected = GnssFixStatus::kFix;
    double sigma_h = 1.5;
    if (t >= 10 * kSecond && t < 20 * kSecond) expected = GnssFixStatus::kRtkFixed, sigma_h = 0.02;
    if (t >= 15 * kSecond && t < 18 * kSecond) expected = GnssFixStatus::kRtkFloat, sigma_h = 0.3;
    EXPECT_EQ(gnss.fixes[i].status, expected) << t;
    EXPECT_DOUBLE_EQ(gnss.fixes[i].covariance_enu(0, 0), sigma_h * sigma_h) << t;
    EXPECT_DOUBLE_EQ(gnss.fixes[i].covariance_enu(1, 1), sigma_h * sigma_h) << t;
    if (expected == GnssFixStatus::kRtkFixed) {
      ++counts[0];
      EXPECT_LT(errors[i].head<2>().norm(), 5.0 * 0.02) << t;
    }
    if (expected == GnssFixStatus::kRtkFloat) ++counts[1];
    if (expected == GnssFixStatus::kFix) ++counts[2];
  }
  EXPECT_EQ(counts[0], 35);  // [10, 15) and [18, 20) s at 5 Hz
  EXPECT_EQ(counts[1], 15);
  EXPECT_EQ(counts[2], 101);
}

TEST(GnssModelTest, TheSameSeedGivesTheSameFixes) {
  const SimulatedGnss a = Simulate(Smooth(), GnssConfig{}, 0, 20 * kSecond, 42);
  const SimulatedGnss b = Simulate(Smooth(), GnssConfig{}, 0, 20 * kSecond, 42);
  const SimulatedGnss c = Simulate(Smooth(), GnssConfig{}, 0, 20 * kSecond, 43);
  ASSERT_EQ(a.fixes.size(), c.fixes.size());
  for (std::size_t i = 0; i < a.fixes.size(); ++i) {
    EXPECT_EQ(a.fixes[i].latitude_deg, b.fixes[i].latitude_deg);
    EXPECT_EQ(a.fixes[i].longitude_deg, b.fixes[i].longitude_deg);
    EXPECT_EQ(a.fixes[i].altitude_m, b.fixes[i].altitude_m);
    EXPECT_NE(a.fixes[i].latitude_deg, c.fixes[i].latitude_deg);
  }
}

TEST(GnssModelTest, BadConfigurationsNameTheFieldAndValue) {
  const auto error = [](const GnssConfig& config, const GeodeticOrigin& origin = kOrigin) {
    const Expected<GnssSimulator> simulator = GnssSimulator::Create(Still(), SE3(), config, origin, 1);
    return simulator.ok() ? std::string("ok") : simulator.error();
  };
  EXPECT_EQ(error(GnssConfig{}), "ok");
  GnssConfig config;
  config.rate_hz = 0;
  EXPECT_EQ(error(config), "gnss.rate_hz: must be in (0, 1000], got 0");
  config = GnssConfig{};
  config.single.horizontal_std_m = -1;
  EXPECT_EQ(error(config), "gnss.single.horizontal_std_m: must be finite and >= 0, got -1");
  config = GnssConfig{};
  config.rtk_float.correlation_time_s = std::nan("");
  EXPECT_EQ(error(config), "gnss.rtk_float.correlation_time_s: must be finite and >= 0, got nan");
  config = GnssConfig{};
  config.outages = {TimeWindow{2 * kSecond, kSecond}};
  EXPECT_EQ(error(config), "gnss.outages[0]: end 1.000000000 s is before begin 2.000000000 s");
  config = GnssConfig{};
  config.multipath = {{TimeWindow{0, kSecond}, Vector3d(0, std::nan(""), 0)}};
  EXPECT_EQ(error(config), "gnss.multipath[0].offset: must be finite, got (0, nan, 0)");
  config = GnssConfig{};
  config.quality_changes = {{TimeWindow{0, kSecond}, static_cast<GnssQuality>(7)}};
  EXPECT_EQ(error(config), "gnss.quality_changes[0].quality: unknown value 7");
  EXPECT_EQ(error(GnssConfig{}, GeodeticOrigin{95.0, 0.0, 0.0}),
            "gnss.origin.latitude_deg: must be in [-90, 90], got 95");

  Expected<GnssSimulator> simulator = GnssSimulator::Create(Still(), SE3(), GnssConfig{}, kOrigin, 1);
  ASSERT_TRUE(simulator.ok());
  EXPECT_FALSE(simulator->Generate(2 * kSecond, kSecond).ok());
  EXPECT_FALSE(simulator->Generate(0, 40000 * kSecond).ok());
}

}  // namespace
}  // namespace uf::sim
