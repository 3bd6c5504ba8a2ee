// What stands between a GNSS fix and its factor (odometry/estimator/gnss/): the screening and covariance of
// fixes, the ENU origin at the first good fix, the closed-form alignment start against a known yaw and
// translation, the innovation test (statistically, against in-covariance noise and 20 m jumps) and the
// placement of fixes among the window's nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "odometry/estimator/gnss/alignment_init.h"
#include "odometry/estimator/gnss/fix_placement.h"
#include "odometry/estimator/gnss/fix_screening.h"
#include "odometry/estimator/gnss/gnss_enu_origin.h"
#include "odometry/estimator/gnss/integrity_check.h"

namespace uf::estimator {
namespace {

constexpr double kPi = 3.14159265358979323846;

GnssFix GoodFix() {
  GnssFix fix;
  fix.stamp = 1'700'000'000'000'000'000;
  fix.latitude_deg = 48.137154;
  fix.longitude_deg = 11.576124;
  fix.altitude_m = 565.3;
  fix.covariance_enu = Eigen::Vector3d(2.25, 2.25, 9.0).asDiagonal();
  fix.status = GnssFixStatus::kFix;
  return fix;
}

TEST(GnssScreening, RejectsBadFixesAndSaysWhy) {
  const GnssFactorConfig config;
  EXPECT_FALSE(ScreenFix(GoodFix(), config));
  auto reason = [&](auto change, const GnssFactorConfig& c = GnssFactorConfig()) {
    GnssFix fix = GoodFix();
    change(fix);
    const std::optional<std::string> why = ScreenFix(fix, c);
    return why ? *why : std::string("accepted");
  };
  EXPECT_EQ(reason([](GnssFix& f) { f.status = GnssFixStatus::kNoFix; }), "no fix");
  EXPECT_NE(reason([](GnssFix& f) { f.latitude_deg = std::nan(""); }).find("non-finite position"),
            std::string::npos);
  EXPECT_NE(reason([](GnssFix& f) {
              f.longitude_deg = std::numeric_limits<double>::infinity();
            }).find("non-finite position"),
            std::string::npos);
  EXPECT_EQ(reason([](GnssFix& f) { f.latitude_deg = 91; }), "latitude 91 deg is outside [-90, 90]");
  EXPECT_EQ(reason([](GnssFix& f) { f.longitude_deg = -180.5; }),
            "longitude -180.5 deg is outside [-180, 180]");
  EXPECT_EQ(reason([](GnssFix& f) { f.altitude_m = 2e5; }), "altitude 200000 m is outside [-12000, 100000]");
  EXPECT_EQ(reason([](GnssFix& f) { f.covariance_enu.setZero(); }), "all-zero covariance (accuracy unknown)");
  EXPECT_NE(
      reason([](GnssFix& f) { f.covariance_enu = -f.covariance_enu; }).find("not positive semidefinite"),
      std::string::npos);
  EXPECT_NE(reason([](GnssFix& f) { f.covariance_enu(1, 1) = -0.5; }).find("not positive semidefinite"),
            std::string::npos);
  EXPECT_EQ(reason([](GnssFix& f) { f.covariance_enu(0, 1) = 1.0; }), "covariance not symmetric");
  EXPECT_EQ(reason([](GnssFix& f) { f.covariance_enu(2, 2) = std::nan(""); }), "non-finite covariance");
  GnssFactorConfig rtk_only;
  rtk_only.min_status = GnssFixStatus::kRtkFloat;
  EXPECT_EQ(reason([](GnssFix&) {}, rtk_only), "status fix is below the minimum rtk_float");
  EXPECT_EQ(reason([](GnssFix& f) { f.status = GnssFixStatus::kRtkFixed; }, rtk_only), "accepted");
  // A singular but positive semidefinite covariance is accepted (the floor makes it definite).
  EXPECT_EQ(reason([](GnssFix& f) { f.covariance_enu(2, 2) = 0; }), "accepted");
}

TEST(GnssScreening, CovarianceGetsTheStatusScaleFloorAndNominalSigmas) {
  GnssFactorConfig config;
  config.fix.sigma_scale = 2.0;
  GnssFix fix = GoodFix();  // sigmas 1.5, 1.5, 3 -> scaled 3, 3, 6
  EXPECT_LT((FixCovariance(fix, config) - Eigen::Matrix3d(Eigen::Vector3d(9, 9, 36).asDiagonal())).norm(),
            1e-9);
  // RTK fixed with a reported 1 mm: floored at 1 cm; a rotated covariance keeps its axes.
  fix.status = GnssFixStatus::kRtkFixed;
  const Eigen::Matrix3d V = SO3::Exp(Eigen::Vector3d(0.3, -0.2, 0.9)).matrix();
  fix.covariance_enu = V * Eigen::Vector3d(1e-6, 4e-4, 9e-4).asDiagonal() * V.transpose();
  const Eigen::Matrix3d expected = V * Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal() * V.transpose();
  EXPECT_LT((FixCovariance(fix, config) - expected).norm(), 1e-12);
  // An unknown (zero) covariance is used only when asked, with the nominal sigmas.
  fix = GoodFix();
  fix.covariance_enu.setZero();
  EXPECT_TRUE(ScreenFix(fix, config));
  config.use_nominal_for_unknown = true;
  EXPECT_FALSE(ScreenFix(fix, config));
  EXPECT_TRUE(HasUnknownCovariance(fix));
  const double h = 2 * config.fix.nominal_horizontal_sigma_m, v = 2 * config.fix.nominal_vertical_sigma_m;
  EXPECT_LT((FixCovariance(fix, config) - Eigen::Matrix3d(Eigen::Vector3d(h * h, h * h, v * v).asDiagonal()))
                .norm(),
            1e-9);
}

TEST(GnssEnuOrigin, IsPlacedAtTheFirstFixAndConvertsTheNext) {
  GnssEnuOrigin origin;
  EXPECT_FALSE(origin.has_origin());
  const GnssFix first = GoodFix();
  auto at_first = origin.ToEnu(first);
  ASSERT_TRUE(at_first) << at_first.error();
  EXPECT_LT(at_first->norm(), 1e-9);
  ASSERT_TRUE(origin.has_origin());
  EXPECT_EQ(origin.frame()->origin().latitude_deg, first.latitude_deg);
  GnssFix second = first;
  second.latitude_deg += 1e-3;  // ~111 m north
  second.altitude_m += 2;
  auto at_second = origin.ToEnu(second);
  ASSERT_TRUE(at_second);
  EXPECT_NEAR(at_second->y(), 111.2, 0.2);
  EXPECT_NEAR(at_second->x(), 0, 1e-6);
  EXPECT_NEAR(at_second->z(), 2, 1e-2);
  const Eigen::Vector3d back = origin.frame()->GeodeticFromEnu(*at_second);
  EXPECT_NEAR(back.x(), second.latitude_deg, 1e-11);
}

// Noisy pairs along a curved path: world positions, fixes through a known alignment plus noise.
std::vector<AlignmentPair> NoisyPairs(const EnuAlignment& truth, double length_m, double sigma_m, int count,
                                      std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  std::vector<AlignmentPair> pairs;
  for (int i = 0; i < count; ++i) {
    const double s = length_m * i / (count - 1);
    const Eigen::Vector3d world(s, 0.2 * s * s / length_m, 0.05 * s);  // ends at (L, L / 5, L / 20)
    const Eigen::Vector3d noise(normal(random), normal(random), 2 * normal(random));
    pairs.push_back({world, truth.Apply(world) + sigma_m * noise, 1.0 / (sigma_m * sigma_m)});
  }
  return pairs;
}

TEST(GnssAlignmentInit, RecoversAKnownYawAndTranslationFromNoisyPairs) {
  std::mt19937_64 random(3);
  const GnssFactorConfig config;
  for (double yaw : {-2.9, -1.0, 0.0, 0.6, 2.2}) {
    const EnuAlignment truth{yaw, Eigen::Vector3d(-35.0, 812.5, 47.0)};
    // Without noise: exact.
    auto exact = InitializeAlignment(NoisyPairs(truth, 60, 0.0 + 1e-12, 20, random), config);
    ASSERT_TRUE(exact) << exact.error();
    EXPECT_NEAR(exact->alignment.yaw_rad, yaw, 1e-9);
    EXPECT_LT((exact->alignment.translation - truth.translation).norm(), 1e-8);
    EXPECT_LT(exact->rms_m, 1e-9);
    // Single-point noise (1.5 m horizontal, 3 m vertical) over 200 m and 100 fixes: yaw to ~1 deg.
    auto noisy = InitializeAlignment(NoisyPairs(truth, 200, 1.5, 100, random), config);
    ASSERT_TRUE(noisy) << noisy.error();
    EXPECT_NEAR(noisy->alignment.yaw_rad, yaw, 1.5 * kPi / 180) << yaw;
    EXPECT_LT((noisy->alignment.translation - truth.translation).head<2>().norm(), 1.5);
    EXPECT_NEAR(noisy->alignment.translation.z(), truth.translation.z(), 1.5);
    EXPECT_NEAR(noisy->rms_m, 1.5 * std::sqrt(6.0), 0.6);  // sqrt(1.5^2 + 1.5^2 + 3^2)
    EXPECT_EQ(noisy->pairs, 100);
    EXPECT_NEAR(noisy->baseline_m, std::hypot(200.0, 40.0), 1e-9);  // the path's end: (200, 40)
  }
}

TEST(GnssAlignmentInit, RefusesTooShortABaselineTooFewFixesAndALargeResidual) {
  std::mt19937_64 random(4);
  const GnssFactorConfig config;  // 10 m, 5 fixes, 10 m RMS
  const EnuAlignment truth{1.0, Eigen::Vector3d(5, 6, 7)};
  auto short_baseline = InitializeAlignment(NoisyPairs(truth, 8, 0.1, 20, random), config);
  ASSERT_FALSE(short_baseline);
  EXPECT_NE(short_baseline.error().find("horizontal baseline 8"), std::string::npos)
      << short_baseline.error();
  auto few = InitializeAlignment(NoisyPairs(truth, 50, 0.1, 4, random), config);
  ASSERT_FALSE(few);
  EXPECT_NE(few.error().find("4 fixes, need 5"), std::string::npos) << few.error();
  auto wild = InitializeAlignment(NoisyPairs(truth, 50, 20, 20, random), config);
  ASSERT_FALSE(wild);
  EXPECT_NE(wild.error().find("residual RMS"), std::string::npos) << wild.error();
  // Vertical travel alone is no baseline.
  std::vector<AlignmentPair> climb;
  for (int i = 0; i < 10; ++i)
    climb.push_back({Eigen::Vector3d(0, 0, 5.0 * i), Eigen::Vector3d(0, 0, 5.0 * i)});
  EXPECT_DOUBLE_EQ(HorizontalBaseline(climb), 0.0);
  EXPECT_FALSE(InitializeAlignment(climb, config));
}

// Fix sigmas (horizontal, vertical) of the simulator's qualities (odometry/sim/gnss_model.h).
struct Quality {
  const char* name;
  double horizontal_m, vertical_m;
};
constexpr Quality kQualities[] = {{"single", 1.5, 3.0}, {"rtk_float", 0.3, 0.5}, {"rtk_fixed", 0.02, 0.04}};

TEST(GnssIntegrity, AcceptsInCovarianceNoise) {
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal;
  const EnuAlignment alignment{0.4, Eigen::Vector3d(10, -20, 3)};
  for (const Quality& quality : kQualities) {
    const Eigen::Vector3d sigma(quality.horizontal_m, quality.horizontal_m, quality.vertical_m);
    const Eigen::Matrix3d covariance = sigma.cwiseAbs2().asDiagonal();
    for (double prediction_sigma : {1.0, 0.0}) {  // the default, and the fix's covariance alone
      GnssFactorConfig config;
      config.prediction_sigma_m = prediction_sigma;
      int accepted = 0;
      double sum_d2 = 0;
      for (int draw = 0; draw < 1000; ++draw) {
        const Eigen::Vector3d predicted(normal(random) * 100, normal(random) * 100, normal(random));
        const Eigen::Vector3d noise =
            sigma.cwiseProduct(Eigen::Vector3d(normal(random), normal(random), normal(random)));
        const IntegrityResult result =
            CheckIntegrity(predicted, alignment, alignment.Apply(predicted) + noise, covariance, 0.0, config);
        accepted += result.accepted;
        sum_d2 += result.d2;
        EXPECT_LT((result.innovation + noise).norm(), 1e-9);
      }
      EXPECT_GE(accepted, 990) << quality.name << " prediction sigma " << prediction_sigma;
      // With the fix's covariance alone d^2 is chi-square with 3 dof: mean 3 (the mean of 1000 has sd 0.08).
      if (prediction_sigma == 0) {
        EXPECT_NEAR(sum_d2 / 1000, 3.0, 0.3) << quality.name;
      }
    }
  }
}

TEST(GnssIntegrity, RejectsA20mJump) {
  // A 20 m jump on top of in-covariance noise, in a random direction, at the default gate and prediction
  // sigma. For single-point fixes the jumps are horizontal: a vertical 20 m jump of a 3 m-sigma fix is
  // rejected on its own (d^2 = 400 / (9 + 1) = 40 > 16.27) but not under every noise draw (-2.4 sigma of
  // noise brings it under the gate), which is the test's statistics, not a fault.
  std::mt19937_64 random(12);
  std::normal_distribution<double> normal;
  const GnssFactorConfig config;
  const EnuAlignment alignment{-2.0, Eigen::Vector3d(0.5, 7, -1)};
  for (const Quality& quality : kQualities) {
    const bool horizontal_only = quality.horizontal_m > 1;
    const Eigen::Vector3d sigma(quality.horizontal_m, quality.horizontal_m, quality.vertical_m);
    const Eigen::Matrix3d covariance = sigma.cwiseAbs2().asDiagonal();
    int rejected = 0;
    for (int draw = 0; draw < 1000; ++draw) {
      Eigen::Vector3d direction(normal(random), normal(random), horizontal_only ? 0.0 : normal(random));
      direction.normalize();
      const Eigen::Vector3d predicted(normal(random) * 100, normal(random) * 100, normal(random));
      const Eigen::Vector3d noise =
          sigma.cwiseProduct(Eigen::Vector3d(normal(random), normal(random), normal(random)));
      const IntegrityResult result = CheckIntegrity(
          predicted, alignment, alignment.Apply(predicted) + noise + 20 * direction, covariance, 0.0, config);
      rejected += !result.accepted;
    }
    EXPECT_EQ(rejected, 1000) << quality.name;
    // Straight up, without noise.
    const IntegrityResult up =
        CheckIntegrity(Eigen::Vector3d::Zero(), alignment, alignment.translation + Eigen::Vector3d(0, 0, 20),
                       covariance, 0.0, config);
    EXPECT_FALSE(up.accepted) << quality.name << " d2 " << up.d2;
  }
  // Non-finite input is never accepted.
  const IntegrityResult nan =
      CheckIntegrity(Eigen::Vector3d(std::nan(""), 0, 0), alignment, Eigen::Vector3d::Zero(),
                     Eigen::Matrix3d::Identity(), 0.0, config);
  EXPECT_FALSE(nan.accepted);
  EXPECT_TRUE(std::isinf(nan.d2));
}

TEST(GnssIntegrity, ChiSquareQuantilesOfTheSameTail) {
  // Tables: the 99.9 % quantiles are 10.828 (1 dof), 13.816 (2 dof), 16.266 (3 dof).
  EXPECT_NEAR(ChiSquareQuantile(1e-3, 1), 10.828, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(1e-3, 2), 13.816, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(1e-3, 3), 16.266, 1e-3);
  EXPECT_NEAR(ChiSquareTail(16.27, 3), 1e-3, 1e-5);  // the default gate
}

TEST(GnssIntegrity, AFixWhoseHeightFailsIsUsedHorizontally) {
  // RTK fixed (2 cm / 4 cm), prediction sigma 1 m: S = diag(1.0004, 1.0004, 1.0016). A 20 m height error
  // alone: vertical d^2 = 400 / 1.0016 = 399 > 10.83 (the height fails), horizontal d^2 = 0 (passes). The
  // same 20 m to the east fails horizontally: rejected outright.
  const GnssFactorConfig config;
  const EnuAlignment alignment{0.3, Eigen::Vector3d(1, 2, 3)};
  const Eigen::Matrix3d covariance = Eigen::Vector3d(4e-4, 4e-4, 1.6e-3).asDiagonal();
  const Eigen::Vector3d predicted(10, 20, 1);
  const IntegrityResult up = CheckIntegrity(
      predicted, alignment, alignment.Apply(predicted) + Eigen::Vector3d(0, 0, 20), covariance, 0.0, config);
  EXPECT_FALSE(up.accepted);
  EXPECT_TRUE(up.horizontal_accepted);
  EXPECT_NEAR(up.d2_vertical, 400 / 1.0016, 1e-9);
  EXPECT_NEAR(up.d2_horizontal, 0, 1e-12);
  const IntegrityResult east = CheckIntegrity(
      predicted, alignment, alignment.Apply(predicted) + Eigen::Vector3d(20, 0, 0), covariance, 0.0, config);
  EXPECT_FALSE(east.horizontal_accepted);
  EXPECT_NEAR(east.d2_horizontal, 400 / 1.0004, 1e-9);
}

TEST(GnssIntegrity, ThePredictionUncertaintyGrowsWithTheDistanceSinceTheLastAcceptedFix) {
  // Defaults: prediction sigma 1 m, drift 5 % of the distance d. A single fix of 1.5 m horizontal sigma,
  // e m east of the prediction: on the east axis S = 2.25 + 1 + (0.05 d)^2, so d^2 = e^2 / (3.25 + 0.0025
  // d^2). e = 6 m: 11.1 right after an accepted fix, 0.92 after 120 m. e = 10 m: 30.8 right after
  // (rejected), 3.5 after 100 m (accepted: a drift the odometry may gather there). A 20 m jump 10 m after
  // an accepted fix: 400 / 3.5 = 114, rejected.
  const GnssFactorConfig config;
  const EnuAlignment alignment{0.0, Eigen::Vector3d::Zero()};
  const Eigen::Matrix3d covariance = Eigen::Vector3d(2.25, 2.25, 9.0).asDiagonal();
  const Eigen::Vector3d predicted(50, -20, 2);
  auto check = [&](double east_m, double distance_m) {
    return CheckIntegrity(predicted, alignment, predicted + Eigen::Vector3d(east_m, 0, 0), covariance,
                          distance_m, config);
  };
  EXPECT_NEAR(check(6, 0).d2, 36 / 3.25, 1e-9);
  EXPECT_NEAR(check(6, 120).d2, 36 / 39.25, 1e-9);
  EXPECT_FALSE(check(10, 0).accepted);
  EXPECT_NEAR(check(10, 100).d2, 100 / 28.25, 1e-9);
  EXPECT_TRUE(check(10, 100).accepted);
  EXPECT_NEAR(check(20, 10).d2, 400 / 3.5, 1e-9);
  EXPECT_FALSE(check(20, 10).accepted);
}

TEST(GnssFixPlacement, InterpolatesSnapsOrLeavesOut) {
  const GnssFactorConfig config;  // gap 1 s, snap 0.05 s
  const Stamp s = kNanosecondsPerSecond;
  const std::vector<Stamp> nodes = {10 * s, 10 * s + s / 10, 10 * s + s / 5, 15 * s};
  auto place = [&](Stamp t) { return PlaceFix(t, nodes, config); };
  auto between = place(10 * s + s / 20);  // halfway between nodes 0 and 1
  ASSERT_TRUE(between);
  EXPECT_EQ(between->node_a, 0u);
  EXPECT_EQ(between->node_b, 1u);
  EXPECT_NEAR(between->alpha, 0.5, 1e-12);
  auto at_node = place(10 * s + s / 10);
  ASSERT_TRUE(at_node);
  EXPECT_TRUE(at_node->single_node());
  EXPECT_EQ(at_node->node_a, 1u);
  // In the 4.8 s gap: near its ends snapped to them, in the middle left out.
  auto near_gap_start = place(10 * s + s / 5 + s / 50);
  ASSERT_TRUE(near_gap_start);
  EXPECT_TRUE(near_gap_start->single_node());
  EXPECT_EQ(near_gap_start->node_a, 2u);
  auto near_gap_end = place(15 * s - s / 50);
  ASSERT_TRUE(near_gap_end);
  EXPECT_EQ(near_gap_end->node_a, 3u);
  EXPECT_FALSE(place(12 * s));
  // Outside the span: snapped within 0.05 s, else left out.
  EXPECT_TRUE(place(10 * s - s / 25));
  EXPECT_FALSE(place(10 * s - s / 10));
  EXPECT_TRUE(place(15 * s + s / 25));
  EXPECT_FALSE(place(16 * s));
  EXPECT_FALSE(PlaceFix(10 * s, std::vector<Stamp>{}, config));
}

}  // namespace
}  // namespace uf::estimator
