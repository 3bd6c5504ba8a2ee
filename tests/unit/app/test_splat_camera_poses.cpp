// Where the images are placed: the camera pose in the map frame from the run's trajectory in each output
// frame and mode, against the camera's true pose composed directly from the body's ground truth; pose
// interpolation; keyframe selection; the camera stream's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "viewer/app/splat_camera_poses.h"
#include "viewer/app/splat_views.h"

namespace uf::app {
namespace {

SE3 Pose(double rx, double ry, double rz, double x, double y, double z) {
  Vector6d xi;
  xi << x, y, z, rx, ry, rz;
  return SE3(SE3::Exp(xi).so3(), Eigen::Vector3d(x, y, z));
}

// Body (dataset frame) with an IMU, a LiDAR and a camera, none at the body origin.
struct Rig {
  SE3 T_body_imu = Pose(0.02, -0.01, 0.03, 0.1, 0.05, -0.02);
  SE3 T_body_lidar = Pose(0.0, 0.05, -0.1, 0.0, 0.1, 0.3);
  SE3 T_body_camera = Pose(-1.5, 0.02, -1.6, 0.4, -0.05, 0.1);
  DatasetDescription description;

  Rig() {
    description.path = "rig";
    StreamInfo imu, lidar, camera;
    imu.name = "imu", imu.kind = SensorKind::kImu, imu.T_body_sensor = T_body_imu;
    lidar.name = "lidar", lidar.kind = SensorKind::kLidar, lidar.T_body_sensor = T_body_lidar;
    camera.name = "cam0", camera.kind = SensorKind::kCamera, camera.T_body_sensor = T_body_camera;
    camera.camera_model =
        std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{64, 48, 50, 50, 31.5, 23.5}});
    description.streams = {imu, lidar, camera};
  }
};

// The body's true pose at time i in a world W.
SE3 TrueBody(int i) { return Pose(0.01 * i, 0.02, 0.1 * i, 1.0 * i, 0.3 * i, 0.05 * i); }

void ExpectSame(const SE3& a, const SE3& b) {
  EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-9) << a.matrix() << "\n" << b.matrix();
}

// The camera pose the views use: T_M_W * T_W_F(t) * T_F_C.
SE3 Placed(const Rig& rig, const std::string& mode, const std::string& frame, const SE3& T_world_frame,
           bool from_trajectory = false) {
  Expected<SplatCameraStream> camera = FindSplatCamera(rig.description, frame);
  EXPECT_TRUE(camera.ok()) << camera.error();
  Expected<SE3> T_map_world = MapFromTrajectoryWorld(rig.description, mode, frame, from_trajectory);
  EXPECT_TRUE(T_map_world.ok());
  return *T_map_world * T_world_frame * camera->T_frame_camera;
}

TEST(SplatCameraPoses, LioInEitherFrameGivesTheCameraInTheEstimatorsWorld) {
  const Rig rig;
  for (int i = 0; i < 4; ++i) {
    const SE3 truth = TrueBody(i) * rig.T_body_camera;
    // LIO estimates the IMU; its world is the map's. Written in the IMU frame, or moved to the LiDAR's.
    ExpectSame(Placed(rig, "lio", "imu", TrueBody(i) * rig.T_body_imu), truth);
    ExpectSame(Placed(rig, "lio", "lidar", TrueBody(i) * rig.T_body_lidar), truth);
  }
}

TEST(SplatCameraPoses, LoInTheImuFrameIsMovedBackIntoTheLidarWorldOfTheMap) {
  const Rig rig;
  // LO: the world is the first LiDAR pose; the map is built there.
  const SE3 T_L0_W = (TrueBody(0) * rig.T_body_lidar).inverse();
  const SE3 T_imu_lidar = rig.T_body_imu.inverse() * rig.T_body_lidar;
  for (int i = 0; i < 4; ++i) {
    const SE3 T_L0_lidar = T_L0_W * TrueBody(i) * rig.T_body_lidar;
    const SE3 truth = T_L0_W * TrueBody(i) * rig.T_body_camera;
    ExpectSame(Placed(rig, "lo", "lidar", T_L0_lidar), truth);
    // run_outputs.h ToImuFrame: T_imu0_imu(t) = T_imu_lidar T_L0_lidar(t) T_imu_lidar^-1.
    const SE3 T_I0_imu = T_imu_lidar * T_L0_lidar * T_imu_lidar.inverse();
    ExpectSame(Placed(rig, "lo", "imu", T_I0_imu), truth);
    // `run --from map` remade the map in the trajectory's own world.
    ExpectSame(Placed(rig, "lo", "imu", T_I0_imu, true), T_imu_lidar * truth);
  }
}

TEST(SplatCameraPoses, KeyframesAreSelectedByDistanceOrAngle) {
  KeyframeSelector selector(0.3, 5.0);
  EXPECT_TRUE(selector.Select(Pose(0, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(selector.Select(Pose(0, 0, 0, 0.29, 0, 0)));
  EXPECT_TRUE(selector.Select(Pose(0, 0, 0, 0.31, 0, 0)));
  const double four = 4.0 * std::numbers::pi / 180, six = 6.0 * std::numbers::pi / 180;
  EXPECT_FALSE(selector.Select(Pose(0, 0, four, 0.31, 0, 0)));
  EXPECT_TRUE(selector.Select(Pose(0, 0, six, 0.31, 0, 0)));
}

TEST(SplatCameraPoses, CamerasThatCannotBePlacedAreErrorsThatSaySo) {
  Rig rig;
  rig.description.streams[2].camera_model.reset();
  EXPECT_NE(FindSplatCamera(rig.description, "imu").error().find("cam0 has no intrinsics"),
            std::string::npos);
  rig = Rig();
  rig.description.streams[2].T_body_sensor.reset();
  EXPECT_NE(FindSplatCamera(rig.description, "imu").error().find("no extrinsic"), std::string::npos);
  rig.description.streams.pop_back();
  EXPECT_NE(FindSplatCamera(rig.description, "imu").error().find("no camera stream"), std::string::npos);
}

}  // namespace
}  // namespace uf::app
