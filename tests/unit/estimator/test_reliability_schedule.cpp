// The reliability scheduling's parts (docs/METHOD.md "Factor-wise reliability scheduling"): the activation
// gate's hysteresis on constructed score sequences, the wheel score against hand-computed motions, the GNSS
// and IMU scores' sums, and the GNSS step guard on constructed innovation sequences.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "odometry/estimator/schedule/activation_gate.h"
#include "odometry/estimator/schedule/gnss_score.h"
#include "odometry/estimator/schedule/gnss_step_guard.h"
#include "odometry/estimator/schedule/imu_score.h"
#include "odometry/estimator/schedule/wheel_consistency.h"

namespace uf::estimator {
namespace {

std::vector<bool> Gate(const ActivationRule& rule, const std::vector<double>& scores, int count = 10) {
  ActivationGate gate(rule);
  std::vector<bool> active;
  for (double score : scores) active.push_back(gate.Update(score, count));
  return active;
}

TEST(ActivationGate, ShutsAtTheFirstScoreAboveTauAndOpensAfterCalmKeyframes) {
  const ActivationRule rule{.threshold = 0.5, .release_margin = 0.1, .release_keyframes = 3};
  EXPECT_EQ(Gate(rule, {0.1, 0.5, 0.51, 0.3, 0.4, 0.3, 0.2, 0.45, 0.1}),
            (std::vector<bool>{true, true, false, false, false, true, true, true, true}));
  // 0.4 is the release level (tau - margin): it counts; a keyframe above it starts the count again.
  EXPECT_EQ(Gate(rule, {0.9, 0.4, 0.4, 0.41, 0.4, 0.4, 0.4}),
            (std::vector<bool>{false, false, false, false, false, false, true}));
  // Not finite: not trusted.
  EXPECT_EQ(Gate(rule, {std::nan("")}), (std::vector<bool>{false}));
}

TEST(ActivationGate, DoesNotChatterOnAScoreOscillatingAboutTau) {
  const ActivationRule rule{.threshold = 0.5, .release_margin = 0.1, .release_keyframes = 3};
  std::vector<double> scores;
  for (int k = 0; k < 200; ++k) scores.push_back(0.5 + 0.05 * std::sin(0.9 * k));  // within +-0.05 of tau
  const std::vector<bool> active = Gate(rule, scores);
  int switches = 0;
  for (std::size_t k = 1; k < active.size(); ++k) switches += active[k] != active[k - 1];
  EXPECT_EQ(switches, 1);  // shut once, never opened: the score never reaches the release level
  EXPECT_FALSE(active.back());
  // Without hysteresis (no margin, one keyframe) the same score switches at almost every crossing.
  const std::vector<bool> bare =
      Gate({.threshold = 0.5, .release_margin = 0.0, .release_keyframes = 1}, scores);
  int bare_switches = 0;
  for (std::size_t k = 1; k < bare.size(); ++k) bare_switches += bare[k] != bare[k - 1];
  EXPECT_GT(bare_switches, 50);
}

TEST(ActivationGate, TooFewObservationsShutIt) {
  const ActivationRule rule{.threshold = 0.5, .release_margin = 0.1, .release_keyframes = 2, .min_count = 20};
  ActivationGate gate(rule);
  EXPECT_TRUE(gate.Update(0.1, 25));
  EXPECT_FALSE(gate.Update(0.1, 19));
  EXPECT_FALSE(gate.Update(0.1, 25));
  EXPECT_TRUE(gate.Update(0.1, 25));
}

// Body motions over 0.1 s: the IMU's 1.0 m forward and 0.02 rad of yaw; a level wheel frame 0.3 m behind.
TEST(WheelScore, MeasuresTheDisagreementInTheWheelsPlaneAndAboutItsVertical) {
  const SO3 level;
  const SE3 imu(SO3::Exp(Eigen::Vector3d(0, 0, 0.02)), Eigen::Vector3d(1.0, 0, 0));
  const WheelScoreWeights weights{
      .speed_tolerance_mps = 0.5, .yaw_rate_tolerance_rad_s = 1.0, .speed_weight = 0.5};
  // The wheel says 1.03 m and 0.01 m to the left, 0.05 rad of yaw, and 0.2 m up (not its plane: ignored),
  // with roll (not its axis: ignored).
  const SE3 wheel(SO3::Exp(Eigen::Vector3d(0.03, 0, 0.05)), Eigen::Vector3d(1.03, 0.01, 0.2));
  const Eigen::Vector2d none = Eigen::Vector2d::Zero();
  const WheelScore score = ScoreWheelMotion(wheel, imu, level, 0.1, none, 0.0, weights);
  const WheelConsistency& c = score.consistency;
  EXPECT_TRUE(score.disagreement.isApprox(Eigen::Vector2d(0.3, 0.1), 1e-12)) << score.disagreement;
  EXPECT_NEAR(c.speed_error_mps, std::hypot(0.03, 0.01) / 0.1, 1e-12);
  EXPECT_NEAR(c.yaw_rate_error_rad_s, 0.3, 1e-9);
  EXPECT_NEAR(c.score, 0.5 * (std::hypot(0.03, 0.01) / 0.1) / 0.5 + 0.5 * 0.3, 1e-9);
  EXPECT_TRUE(c.active);
  // Agreeing motions score 0; a 30 % slip at 10 m/s saturates the speed term.
  EXPECT_NEAR(ScoreWheelMotion(imu, imu, level, 0.1, none, 0.0, weights).consistency.score, 0.0, 1e-12);
  const SE3 slipping(imu.so3(), 1.3 * imu.translation());
  EXPECT_NEAR(ScoreWheelMotion(slipping, imu, level, 0.1, none, 0.0, weights).consistency.score, 0.5, 1e-12);
  // The disagreement the window has lately shown (its own velocity error) is taken out: with u_0 = (0.3,
  // 0.1) m/s the same motions leave only the yaw term.
  const Eigen::Vector2d usual(0.3, 0.1);
  EXPECT_NEAR(ScoreWheelMotion(wheel, imu, level, 0.1, usual, 0.0, weights).consistency.speed_error_mps, 0.0,
              1e-12);
  // The disagreement of the speed changes, against its own tolerance (tau_c 1 m/s): 0.4 m/s weighs as a
  // speed disagreement of 0.2 m/s; the larger of the two counts.
  const WheelConsistency changed = ScoreWheelMotion(wheel, imu, level, 0.1, usual, 0.4, weights).consistency;
  EXPECT_NEAR(changed.speed_change_error_mps, 0.4, 1e-12);
  EXPECT_NEAR(changed.score, 0.5 * 0.4 / 1.0 + 0.5 * 0.3, 1e-9);
  // A wheel frame turned 90 degrees about x: its plane is the body's x-z, its vertical the body's -y.
  const SO3 turned = SO3::Exp(Eigen::Vector3d(M_PI / 2, 0, 0));
  const WheelConsistency t = ScoreWheelMotion(wheel, imu, turned, 0.1, none, 0.0, weights).consistency;
  EXPECT_NEAR(t.speed_error_mps, std::hypot(0.03, 0.2) / 0.1, 1e-9);
  EXPECT_NEAR(t.yaw_rate_error_rad_s, 0.0, 1e-9);
  // No interval: no trust.
  EXPECT_EQ(ScoreWheelMotion(wheel, imu, level, 0.0, none, 0.0, weights).consistency.score, 1.0);
}

// The paper's GNSS sum with equal weights, hand-computed: quality, covariance, innovation.
// The IMU score's three terms, hand-computed: at rest with a small residual only the excitation's weight
// counts; turning, a residual past tau_imu and a clipped step give w_p + w_s; half the excitation
// threshold, half the residual threshold; a non-finite residual saturates its term.
TEST(ImuScore, SumsExcitationResidualAndClipping) {
  const ImuReliability rest = ScoreImuInterval({.rate_rad_s = 0, .acceleration_mps2 = 0, .chi2 = 0});
  EXPECT_DOUBLE_EQ(rest.excitation, 0.0);
  EXPECT_DOUBLE_EQ(rest.score, kImuExcitationWeight);
  const ImuReliability bad =
      ScoreImuInterval({.rate_rad_s = 1.0, .acceleration_mps2 = 0, .chi2 = 100, .clipped_steps = 3});
  EXPECT_DOUBLE_EQ(bad.excitation, 1.0);
  EXPECT_EQ(bad.clipped_steps, 3);
  EXPECT_DOUBLE_EQ(bad.score, kImuResidualWeight + kImuClippedWeight);
  const ImuReliability half = ScoreImuInterval({.rate_rad_s = 0.01,
                                                .acceleration_mps2 = 0.5 * kImuAccelExcitation_mps2,
                                                .chi2 = 0.5 * kImuChi2Threshold});
  EXPECT_DOUBLE_EQ(half.excitation, 0.5);
  EXPECT_DOUBLE_EQ(half.score, 0.5 * kImuExcitationWeight + 0.5 * kImuResidualWeight);
  const ImuReliability nan = ScoreImuInterval({.rate_rad_s = 1.0, .chi2 = std::nan("")});
  EXPECT_DOUBLE_EQ(nan.score, kImuResidualWeight);
}

// The GNSS step guard on constructed innovation sequences (5 Hz RTK fixes, 2 cm sigmas, the antenna moving
// 1.5 m per fix): which fixes it admits.
std::vector<bool> GuardAdmits(const std::vector<Eigen::Vector3d>& innovations, double seconds_per_fix = 0.2,
                              double max_hold_s = 30.0) {
  GnssStepGuard guard({.max_hold_s = max_hold_s});
  const Eigen::Matrix3d covariance = Eigen::Vector3d(0.02, 0.02, 0.04).cwiseAbs2().asDiagonal();
  std::vector<bool> admitted;
  for (std::size_t k = 0; k < innovations.size(); ++k)
    admitted.push_back(guard.Admit(FromSeconds(seconds_per_fix * static_cast<double>(k)), innovations[k],
                                   covariance, Eigen::Vector3d(1.5 * static_cast<double>(k), 0, 0)));
  return admitted;
}

TEST(GnssStepGuard, HoldsAStepOutUntilTheInnovationComesBack) {
  // A 5 m multipath over fixes 10..29: held out exactly there.
  std::vector<Eigen::Vector3d> e(40, Eigen::Vector3d(0.01, -0.02, 0.0));
  for (int k = 10; k < 30; ++k) e[k] += Eigen::Vector3d(4, -3, 0);
  const std::vector<bool> admitted = GuardAdmits(e);
  for (int k = 0; k < 40; ++k) EXPECT_EQ(admitted[k], k < 10 || k >= 30) << k;
  // The odometry drifting: the innovation grows by 5 cm per fix to 2 m, no step, nothing held.
  std::vector<Eigen::Vector3d> drift;
  for (int k = 0; k < 40; ++k) drift.emplace_back(0.05 * k, 0, 0);
  for (bool a : GuardAdmits(drift)) EXPECT_TRUE(a);
  // A step that stays: released after max_hold_s (2 s: 10 fixes), then admitted.
  std::vector<Eigen::Vector3d> stays(30, Eigen::Vector3d::Zero());
  for (int k = 10; k < 30; ++k) stays[k] = Eigen::Vector3d(0, 5, 0);
  const std::vector<bool> released = GuardAdmits(stays, 0.2, 2.0);
  for (int k = 0; k < 30; ++k) EXPECT_EQ(released[k], k < 10 || k > 20) << k;
  // Fixes further apart than max_gap_s are not compared: a 5 m difference after 2 s is no step.
  const std::vector<bool> apart = GuardAdmits({Eigen::Vector3d::Zero(), Eigen::Vector3d(5, 0, 0)}, 2.0);
  EXPECT_TRUE(apart[0] && apart[1]);
  // Without a guard (max_hold_s 0) every fix passes.
  for (bool a : GuardAdmits(e, 0.2, 0.0)) EXPECT_TRUE(a);
}

TEST(GnssScore, SumsQualityCovarianceAndInnovation) {
  const GnssCheck rtk = ScoreGnssFix(7, GnssFixStatus::kRtkFixed, 0.001, 0.0, 16.27, true);
  EXPECT_EQ(rtk.stamp, 7);
  EXPECT_NEAR(rtk.score, (0.0 + 0.0001 + 0.0) / 3, 1e-12);
  const GnssCheck single = ScoreGnssFix(8, GnssFixStatus::kFix, 5.0, 8.135, 16.27, true);
  EXPECT_NEAR(single.score, (0.75 + 0.5 + 0.5) / 3, 1e-12);
  // Multipath far off the prediction, a wide covariance, no status: every term saturates.
  const GnssCheck bad = ScoreGnssFix(9, GnssFixStatus::kNoFix, 40.0, 400.0, 16.27, false);
  EXPECT_NEAR(bad.score, 1.0, 1e-12);
  EXPECT_FALSE(bad.active);
  // No prediction (a non-finite d^2): its term counts as saturated.
  EXPECT_NEAR(ScoreGnssFix(9, GnssFixStatus::kSbas, 0.0, std::nan(""), 16.27, false).score, (0.5 + 0 + 1) / 3,
              1e-12);
}

}  // namespace
}  // namespace uf::estimator
