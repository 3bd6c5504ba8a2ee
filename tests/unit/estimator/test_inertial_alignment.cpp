// Inertial initialization (static and LiDAR-aided alignment) against the simulator's true states.
#include <gtest/gtest.h>

#include "odometry/estimator/init/inertial_alignment.h"
#include "tests/unit/estimator/imu_test_support.h"

namespace uf::estimator {
namespace {

using testing::kGyroBias;
using testing::kSecond;

// An arbitrary "lo" world (the first IMU pose of a LiDAR odometry): tilted and shifted from the true one.
const SE3 kLoFromWorld(SO3::Exp(Eigen::Vector3d(0.3, -0.2, 1.1)), Eigen::Vector3d(4, -2, 1));

// Angle between the gravity-aligned world's "down" and the true one, seen in the true world.
double GravityDirectionError(const InertialAlignment& a, const SO3& R_lo_world) {
  const Eigen::Vector3d down_true(0, 0, -1);
  const Eigen::Vector3d down_estimated = (a.R_gravity_lo * R_lo_world).inverse() * down_true;
  return std::acos(std::clamp(down_estimated.dot(down_true), -1.0, 1.0));
}

TEST(InertialAlignment, LidarAidedRecoversGravityVelocitiesAndGyroBias) {
  ImuNoise noise;
  noise.initial_gyro_bias = kGyroBias;
  const ImuSimulator imu = testing::MovingImu(200.0, noise);
  const Stamp t0 = kSecond, dt = kSecond / 10;
  const std::vector<ImuSample> samples = testing::Samples(imu, t0 - kSecond / 10, t0 + 12 * dt);
  std::vector<SE3> poses;
  std::vector<ImuPreintegration> preintegrations;
  for (int k = 0; k <= 10; ++k) {
    poses.push_back(kLoFromWorld * testing::TrueState(imu, t0 + k * dt).T_world_imu);
    if (k == 0) continue;
    auto pre = ImuPreintegration::Between(samples, t0 + (k - 1) * dt, t0 + k * dt, {0, 0, 0}, {0, 0, 0},
                                          ImuNoiseParams());
    ASSERT_TRUE(pre.ok()) << pre.error();
    preintegrations.push_back(*pre);
  }
  auto aligned = LidarAidedAlignment(poses, preintegrations, InertialInitConfig());
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_EQ(aligned->mode, "lidar-aided");
  EXPECT_LT((aligned->gyro_bias - kGyroBias).norm(), 2e-4);
  EXPECT_NEAR(aligned->gravity_estimate, ImuNoiseParams().gravity, 0.02);
  EXPECT_LT(GravityDirectionError(*aligned, kLoFromWorld.so3()), 1e-3);
  // The aligned world differs from the true one by a yaw: speeds and vertical velocities agree.
  for (int k = 0; k <= 10; ++k) {
    const Eigen::Vector3d v_true = testing::TrueState(imu, t0 + k * dt).velocity;
    const Eigen::Vector3d& v = aligned->velocities[static_cast<std::size_t>(k)];
    EXPECT_NEAR(v.norm(), v_true.norm(), 0.01) << "node " << k;
    EXPECT_NEAR(v.z(), v_true.z(), 0.01) << "node " << k;
  }
}

TEST(InertialAlignment, LidarAidedRejectsPosesInWrongUnits) {
  const ImuSimulator imu = testing::MovingImu(200.0);
  const Stamp t0 = kSecond, dt = kSecond / 10;
  const std::vector<ImuSample> samples = testing::Samples(imu, t0 - dt, t0 + 12 * dt);
  std::vector<SE3> poses;
  std::vector<ImuPreintegration> preintegrations;
  for (int k = 0; k <= 10; ++k) {
    const SE3 T = testing::TrueState(imu, t0 + k * dt).T_world_imu;
    poses.emplace_back(T.so3(), 100 * T.translation());  // a LiDAR in centimetres
    if (k > 0)
      preintegrations.push_back(
          *ImuPreintegration::Between(samples, t0 + (k - 1) * dt, t0 + k * dt, {0, 0, 0}, {0, 0, 0}, {}));
  }
  auto aligned = LidarAidedAlignment(poses, preintegrations, InertialInitConfig());
  ASSERT_FALSE(aligned.ok());
  EXPECT_NE(aligned.error().find("estimated gravity"), std::string::npos) << aligned.error();
}

TEST(InertialAlignment, StaticFindsTiltAndGyroBiasAtRest) {
  const SE3 tilted(SO3::Exp(Eigen::Vector3d(0.2, -0.15, 0.7)), Eigen::Vector3d(1, 2, 3));
  const std::vector<SE3> control(6, tilted);
  ImuNoise noise;
  noise.gyro_noise_density = 1.7e-4;
  noise.accel_noise_density = 2e-3;
  noise.initial_gyro_bias = kGyroBias;
  auto imu = ImuSimulator::Create(TrajectorySpline::FromControlPoints(0, kSecond / 2, control), SE3(), 200.0,
                                  noise, 7);
  ASSERT_TRUE(imu.ok()) << imu.error();
  const std::vector<ImuSample> samples = testing::Samples(*imu, kSecond / 2, kSecond);
  const std::vector<SE3> poses(5, SE3());  // LO at rest, in the frame of the first IMU pose
  const double gravity = ImuNoiseParams().gravity;
  const std::vector<Stamp> stamps = {kSecond / 2, kSecond * 6 / 10, kSecond * 7 / 10, kSecond * 8 / 10,
                                     kSecond};
  auto aligned = StaticAlignment(ComputeInitIndicators(samples, stamps, poses, 0.0, gravity), poses,
                                 InertialInitConfig(), gravity);
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_EQ(aligned->mode, "static");
  // The lo world is the imu frame: the aligned "down" seen in the imu frame is the true one.
  EXPECT_LT(GravityDirectionError(*aligned, tilted.so3().inverse()), 1e-3);
  EXPECT_LT((aligned->gyro_bias - kGyroBias).norm(), 5e-4);  // white noise 1.7e-4 * sqrt(200 / 100 samples)
  for (const Eigen::Vector3d& v : aligned->velocities) EXPECT_EQ(v, Eigen::Vector3d::Zero());
}

TEST(InertialAlignment, StaticRejectsMotion) {
  const ImuSimulator imu = testing::MovingImu(200.0);
  const std::vector<ImuSample> samples = testing::Samples(imu, kSecond, 2 * kSecond);
  const std::vector<SE3> poses(5, SE3());
  const std::vector<Stamp> stamps = {kSecond, kSecond * 5 / 4, kSecond * 3 / 2, kSecond * 7 / 4, 2 * kSecond};
  auto aligned = StaticAlignment(ComputeInitIndicators(samples, stamps, poses, 0.0, 9.80665), poses,
                                 InertialInitConfig(), 9.80665);
  ASSERT_FALSE(aligned.ok());
  EXPECT_NE(aligned.error().find("not static"), std::string::npos) << aligned.error();
}

TEST(InertialAlignment, ConfigNamesBadField) {
  InertialInitConfig config;
  config.max_gravity_error = 1.5;
  EXPECT_NE(config.Validate().message().find("lio.init.max_gravity_error"), std::string::npos);
}

}  // namespace
}  // namespace uf::estimator
