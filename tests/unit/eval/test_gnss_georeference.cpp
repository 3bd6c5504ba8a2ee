// The run's georeference from GNSS: a drive with a known T_enu_world, an antenna on a lever arm in the
// dataset's body frame and an estimator that tracks another frame (LO: the LiDAR), fixes with noise and the
// matching covariance (RTK, with a stretch of single-point fixes). The recovered frame is within the error
// that the fixes' covariances predict; too few fixes, too short a path and too large a residual are not
// admitted, and the note says why.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "gnss_test_support.h"
#include "odometry/eval/gnss_georeference.h"

namespace uf {
namespace {

using testing::Drive;

// The dataset's body is its IMU; the GNSS antenna sits 1.3 m above it, behind and to the left.
const SE3 kBodyFromGnss(SO3::Exp(Eigen::Vector3d(0, 0, 0.3)), Eigen::Vector3d(-0.4, 0.25, 1.3));
// LO estimates the LiDAR, mounted 1.2 m ahead and turned 90 degrees: T_estimator_body = T_lidar_body.
const SE3 kBodyFromLidar(SO3::Exp(Eigen::Vector3d(0, 0, std::numbers::pi / 2)), Eigen::Vector3d(1.2, 0, 0.6));

constexpr double kRtkSigma = 0.03, kSingleSigma = 2.0;  // m per axis
// RTK fixes, with single-point ones over poses 100..199 (10..20 s: an urban canyon).
double CanyonSigma(std::size_t pose) { return pose >= 100 && pose < 200 ? kSingleSigma : kRtkSigma; }

// Predicted covariance of where the alignment puts the world point p, from the fixes' covariances
// sigma_i^2 I (weights w_i = 1 / sigma_i^2, as AlignToGnss weighs them). Linearised about the truth, the
// fit's translation at the weighted centroid c of the antenna positions a_i and its small rotation dtheta
// are independent, with
//   cov(dt_c) = I / sum_i w_i,   cov(dtheta) = (sum_i w_i (|d_i|^2 I - d_i d_i^T))^-1,   d_i = a_i - c,
// so p's error dt_c + dtheta x (p - c) has covariance cov(dt_c) + [p - c]x cov(dtheta) [p - c]x^T. The
// yaw-only fit has no roll or pitch error, so for it this is an upper bound.
Eigen::Matrix3d PredictedCovariance(const std::vector<Eigen::Vector3d>& antenna,
                                    const std::vector<double>& sigma, const Eigen::Vector3d& p) {
  double weight_sum = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < antenna.size(); ++i) {
    weight_sum += 1 / (sigma[i] * sigma[i]);
    c += antenna[i] / (sigma[i] * sigma[i]);
  }
  c /= weight_sum;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < antenna.size(); ++i) {
    const Eigen::Vector3d d = antenna[i] - c;
    information +=
        (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()) / (sigma[i] * sigma[i]);
  }
  const Eigen::Matrix3d lever = Hat(p - c);
  return Eigen::Matrix3d::Identity() / weight_sum + lever * information.inverse() * lever.transpose();
}

struct Case {
  const char* name;
  bool gravity_aligned;
  SE3 T_enu_world;
};

TEST(GnssGeoreference, RecoversTheWorldWithinTheNoiseOfTheFixes) {
  const Trajectory trajectory = Drive();  // T_world_lidar: the estimator's body is the LiDAR
  const SE3 T_estimator_body = kBodyFromLidar.inverse();
  const Eigen::Vector3d antenna = (T_estimator_body * kBodyFromGnss).translation();
  for (const Case& c :
       {Case{"LIO, gravity-aligned", true,
             SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.7)), Eigen::Vector3d(120, -40, 3))},
        Case{"LO", false, SE3(SO3::Exp(Eigen::Vector3d(0.05, -0.08, 2.0)), Eigen::Vector3d(-7, 15, -2))}}) {
    SCOPED_TRACE(c.name);
    const std::vector<GnssFix> fixes = testing::Fixes(trajectory, c.T_enu_world, antenna, CanyonSigma);
    const GnssGeoreference found =
        GeoreferenceFromGnss(trajectory, fixes, kBodyFromGnss, T_estimator_body, c.gravity_aligned);
    ASSERT_TRUE(found.alignment.has_value()) << found.note;
    EXPECT_EQ(found.note.rfind("map georeferenced by 151 GNSS fixes (residual RMS ", 0), 0u) << found.note;
    EXPECT_EQ(found.alignment->fixes_used, 151);

    // The antenna positions and noise of the fixes, for the prediction.
    std::vector<Eigen::Vector3d> antenna_world;
    std::vector<double> sigma;
    double mean_squared_noise = 0;
    for (std::size_t k = 0; k < trajectory.size(); k += 2) {
      antenna_world.push_back(trajectory.poses[k] * antenna);
      sigma.push_back(CanyonSigma(k));
      mean_squared_noise += 3 * sigma.back() * sigma.back() / 151;
    }
    // Every pose lies within 4 predicted standard deviations (of the 3D error) of where it truly is; the
    // RTK fixes make that a few centimetres despite the single-point stretch.
    for (const SE3& pose : trajectory.poses) {
      const Eigen::Vector3d p = pose.translation();
      const double bound = 4 * std::sqrt(PredictedCovariance(antenna_world, sigma, p).trace());
      ASSERT_LT(bound, 0.05);
      ASSERT_LT((testing::AlignedInTrueEnu(*found.alignment, p) - c.T_enu_world * p).norm(), bound)
          << p.transpose();
    }
    // The residual RMS is the fixes' noise (sqrt(mean 3 sigma_i^2) = 2.0 m), to its sampling spread.
    EXPECT_NEAR(found.alignment->rms_m, std::sqrt(mean_squared_noise), 0.25 * std::sqrt(mean_squared_noise));
  }
}

TEST(GnssGeoreference, AntennaAtTheBodyOriginWithoutAnExtrinsic) {
  // No T_body_sensor for the GNSS stream: the antenna is taken to be at the dataset body's origin, which
  // here it is; the estimator tracks the body itself (LIO on the IMU).
  const Trajectory trajectory = Drive();
  const SE3 T_enu_world(SO3::Exp(Eigen::Vector3d(0, 0, -1.2)), Eigen::Vector3d(3, 4, 5));
  const std::vector<GnssFix> fixes =
      testing::Fixes(trajectory, T_enu_world, Eigen::Vector3d::Zero(), [](std::size_t) { return kRtkSigma; });
  const GnssGeoreference found = GeoreferenceFromGnss(trajectory, fixes, std::nullopt, SE3(), true);
  ASSERT_TRUE(found.alignment.has_value()) << found.note;
  // 151 fixes of 3 cm: the start pose to a few millimetres, the end (120 m away) to a centimetre or two.
  for (const SE3& pose : {trajectory.poses.front(), trajectory.poses.back()}) {
    const Eigen::Vector3d p = pose.translation();
    EXPECT_LT((testing::AlignedInTrueEnu(*found.alignment, p) - T_enu_world * p).norm(), 0.03);
  }
}

TEST(GnssGeoreference, NotAdmittedSaysWhy) {
  const Trajectory trajectory = Drive();
  const SE3 T_enu_world;
  const Eigen::Vector3d antenna = kBodyFromGnss.translation();
  const auto rtk = [](std::size_t) { return kRtkSigma; };
  const std::vector<GnssFix> fixes = testing::Fixes(trajectory, T_enu_world, antenna, rtk);
  const auto note = [&](std::span<const GnssFix> used) {
    const GnssGeoreference found = GeoreferenceFromGnss(trajectory, used, kBodyFromGnss, SE3(), true);
    EXPECT_FALSE(found.alignment.has_value());
    return found.note;
  };
  // No fixes (no GNSS stream): nothing to say.
  EXPECT_EQ(note({}), "");
  EXPECT_EQ(note(std::span(fixes).first(5)),
            "map not georeferenced: GNSS alignment: 5 fixes within the trajectory's time span, need 10");
  // 12 fixes: 2.2 s, ~9 m of path.
  EXPECT_NE(note(std::span(fixes).first(12)).find("need 20 m for the heading"), std::string::npos);
  // Fixes after the trajectory's end are not used.
  std::vector<GnssFix> late = fixes;
  for (GnssFix& fix : late) fix.stamp += 100 * testing::kSecond;
  EXPECT_EQ(note(late),
            "map not georeferenced: GNSS alignment: 0 fixes within the trajectory's time span, need 10");
  // 30 m of noise: the fit is no better than the fixes.
  const std::vector<GnssFix> noisy =
      testing::Fixes(trajectory, T_enu_world, antenna, [](std::size_t) { return 30.0; });
  const std::string why = note(noisy);
  EXPECT_EQ(why.rfind("map not georeferenced: GNSS alignment: residual RMS ", 0), 0u) << why;
  EXPECT_NE(why.find(" m exceeds 10 m"), std::string::npos) << why;
}

}  // namespace
}  // namespace uf
