// FindSensors and ImuFromSensor against hand-built dataset descriptions: the first stream of each kind, a
// stereo rig's second camera, and T_imu_lidar = T_body_imu^-1 T_body_lidar computed by hand.
#include <gtest/gtest.h>

#include <memory>
#include <numbers>

#include "odometry/io/dataset_sensors.h"
#include "odometry/types/camera_model.h"

namespace uf {
namespace {

StreamInfo Stream(SensorKind kind, std::optional<SE3> T_body_sensor = std::nullopt) {
  StreamInfo stream;
  stream.kind = kind;
  stream.T_body_sensor = T_body_sensor;
  return stream;
}

TEST(DatasetSensors, TheFirstStreamOfEachKind) {
  DatasetDescription description;
  description.streams = {Stream(SensorKind::kCamera), Stream(SensorKind::kImu),   Stream(SensorKind::kLidar),
                         Stream(SensorKind::kGnss),   Stream(SensorKind::kLidar), Stream(SensorKind::kImu)};
  const DatasetSensors sensors = FindSensors(description);
  EXPECT_EQ(sensors.lidar, 2);
  EXPECT_EQ(sensors.imu, 1);
  EXPECT_EQ(sensors.gnss, 3);
  EXPECT_FALSE(sensors.T_imu_lidar);  // the LiDAR has no T_body_sensor

  const DatasetSensors none = FindSensors(DatasetDescription{});
  EXPECT_EQ(none.lidar, -1);
  EXPECT_EQ(none.imu, -1);
  EXPECT_EQ(none.gnss, -1);
}

TEST(DatasetSensors, AStereoPartnerLooksTheSameWayFromNearby) {
  // cam0 looks forward; cam1 0.3 m to its right, cam2 backwards, cam3 5 m away, cam4 without an extrinsic.
  const auto model =
      std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{640, 480, 400, 400, 319.5, 239.5}});
  Eigen::Matrix3d forward;  // optical axis (z) along body x, x along -body y, y along -body z
  forward << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const SE3 left(SO3(forward), Eigen::Vector3d(0.3, 0, 0.1));
  auto camera = [&](std::optional<SE3> T_body_camera) {
    StreamInfo stream = Stream(SensorKind::kCamera, T_body_camera);
    stream.camera_model = model;
    return stream;
  };
  const SE3 backwards =
      SE3(SO3::Exp(Eigen::Vector3d(0, 0, std::numbers::pi)), Eigen::Vector3d::Zero()) * left;
  DatasetDescription description;
  description.streams = {
      Stream(SensorKind::kImu),
      camera(left),
      camera(backwards),
      camera(left * SE3(SO3(), Eigen::Vector3d(5, 0, 0))),
      camera(std::nullopt),
      camera(left * SE3(SO3::Exp(Eigen::Vector3d(0, 0.05, 0)), Eigen::Vector3d(0.3, 0, 0)))};
  DatasetSensors sensors = FindSensors(description);
  EXPECT_EQ(sensors.camera, 1);
  EXPECT_EQ(sensors.camera_right, 5);
  ASSERT_TRUE(sensors.T_imu_camera_right);
  EXPECT_NEAR((sensors.T_imu_camera->inverse() * *sensors.T_imu_camera_right).translation().norm(), 0.3,
              1e-12);
  // Without the partner, no rig: the others are not stereo partners.
  description.streams.pop_back();
  sensors = FindSensors(description);
  EXPECT_EQ(sensors.camera_right, -1);
  EXPECT_FALSE(sensors.T_imu_camera_right);
}

TEST(DatasetSensors, ImuFromSensorComposesTheBodyExtrinsics) {
  // Body = a vehicle frame; IMU 1 m ahead, turned 90 deg about z; LiDAR 2 m up.
  const SE3 T_body_imu(SO3::Exp(Eigen::Vector3d(0, 0, std::numbers::pi / 2)), Eigen::Vector3d(1, 0, 0));
  const SE3 T_body_lidar(SO3(), Eigen::Vector3d(0, 0, 2));
  DatasetDescription description;
  description.streams = {Stream(SensorKind::kLidar, T_body_lidar), Stream(SensorKind::kImu, T_body_imu)};
  const std::optional<SE3> T_imu_lidar = FindSensors(description).T_imu_lidar;
  ASSERT_TRUE(T_imu_lidar);
  // The LiDAR origin, (0, 0, 2) in the body, is (-1, 0, 2) from the IMU in body axes; in the IMU's axes
  // (x along the body's y, y along the body's -x) that is (0, 1, 2). The LiDAR's axes are the body's, so the
  // rotation is the IMU's turn undone: -90 deg about z.
  EXPECT_TRUE(T_imu_lidar->translation().isApprox(Eigen::Vector3d(0, 1, 2), 1e-12));
  EXPECT_TRUE(T_imu_lidar->rotation().isApprox(
      SO3::Exp(Eigen::Vector3d(0, 0, -std::numbers::pi / 2)).matrix(), 1e-12));

  // Without an IMU extrinsic the body is the IMU: T_imu_lidar = T_body_lidar.
  description.streams[1].T_body_sensor.reset();
  EXPECT_TRUE(ImuFromSensor(description, 0)->matrix().isApprox(T_body_lidar.matrix(), 1e-15));
}

}  // namespace
}  // namespace uf
