// The run's frames (run_frames.h) against a rig's true poses: the camera pose in the map frame from the
// run's trajectory in each output frame and mode, against the camera's true pose composed directly from the
// body's ground truth; the trajectory written in each frame; keyframe selection; the camera stream's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/splat/splat_views.h"

namespace uf::pipeline {
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
RunFrames Frames(const Rig& rig, OdometryMode mode, TrajectoryFrame frame, bool from_trajectory = false) {
  Expected<RunFrames> frames = ResolveRunFrames(
      rig.description, mode, frame, from_trajectory ? MapSource::kTrajectory : MapSource::kOdometry);
  EXPECT_TRUE(frames.ok()) << frames.error();
  return *frames;
}

SE3 Placed(const Rig& rig, OdometryMode mode, TrajectoryFrame frame, const SE3& T_world_frame,
           bool from_trajectory = false) {
  const RunFrames frames = Frames(rig, mode, frame, from_trajectory);
  Expected<SplatCameraStream> camera = FindSplatCamera(rig.description, frames.T_output_body);
  EXPECT_TRUE(camera.ok()) << camera.error();
  return frames.T_map_world * T_world_frame * camera->T_frame_camera;
}

constexpr OdometryMode kLo = OdometryMode::kLo, kLio = OdometryMode::kLio;
constexpr TrajectoryFrame kLidar = TrajectoryFrame::kLidar, kImu = TrajectoryFrame::kImu;

TEST(RunFrames, LioInEitherFrameGivesTheCameraInTheEstimatorsWorld) {
  const Rig rig;
  for (int i = 0; i < 4; ++i) {
    const SE3 truth = TrueBody(i) * rig.T_body_camera;
    // LIO estimates the IMU; its world is the map's. Written in the IMU frame, or moved to the LiDAR's.
    ExpectSame(Placed(rig, kLio, kImu, TrueBody(i) * rig.T_body_imu), truth);
    ExpectSame(Placed(rig, kLio, kLidar, TrueBody(i) * rig.T_body_lidar), truth);
  }
}

TEST(RunFrames, LoInTheImuFrameIsMovedBackIntoTheLidarWorldOfTheMap) {
  const Rig rig;
  // LO: the world is the first LiDAR pose; the map is built there.
  const SE3 T_L0_W = (TrueBody(0) * rig.T_body_lidar).inverse();
  const SE3 T_imu_lidar = rig.T_body_imu.inverse() * rig.T_body_lidar;
  for (int i = 0; i < 4; ++i) {
    const SE3 T_L0_lidar = T_L0_W * TrueBody(i) * rig.T_body_lidar;
    const SE3 truth = T_L0_W * TrueBody(i) * rig.T_body_camera;
    ExpectSame(Placed(rig, kLo, kLidar, T_L0_lidar), truth);
    // ToImuFrame: T_imu0_imu(t) = T_imu_lidar T_L0_lidar(t) T_imu_lidar^-1.
    const SE3 T_I0_imu = T_imu_lidar * T_L0_lidar * T_imu_lidar.inverse();
    ExpectSame(Placed(rig, kLo, kImu, T_I0_imu), truth);
    // `run --from map` remade the map in the trajectory's own world.
    ExpectSame(Placed(rig, kLo, kImu, T_I0_imu, true), T_imu_lidar * truth);
  }
}

TEST(RunFrames, TheTrajectoryIsWrittenInTheRequestedFrame) {
  const Rig rig;
  const SE3 T_imu_lidar = rig.T_body_imu.inverse() * rig.T_body_lidar;
  Trajectory imu, lidar;
  for (int i = 0; i < 3; ++i) {
    imu.stamps.push_back(i), lidar.stamps.push_back(i);
    imu.poses.push_back(TrueBody(i) * rig.T_body_imu);
    lidar.poses.push_back(TrueBody(i) * rig.T_body_lidar);
  }
  // LIO (estimates the IMU) written in the LiDAR frame: the same world, the LiDAR's pose.
  const Trajectory lio_lidar = Frames(rig, kLio, kLidar).OutputTrajectory(imu);
  for (int i = 0; i < 3; ++i) ExpectSame(lio_lidar.poses[i], lidar.poses[i]);
  ExpectSame(Frames(rig, kLio, kLidar).T_output_estimator(), T_imu_lidar.inverse());
  ExpectSame(Frames(rig, kLio, kImu).T_estimator_lidar(), T_imu_lidar);
  // LO written in its own frame: unchanged.
  const Trajectory lo_lidar = Frames(rig, kLo, kLidar).OutputTrajectory(lidar);
  for (int i = 0; i < 3; ++i) ExpectSame(lo_lidar.poses[i], lidar.poses[i]);
  ExpectSame(Frames(rig, kLo, kImu).T_output_estimator(), T_imu_lidar);
  ExpectSame(Frames(rig, kLo, kLidar).T_estimator_body, rig.T_body_lidar.inverse());
  ExpectSame(Frames(rig, kLio, kLidar).T_estimator_body, rig.T_body_imu.inverse());
}

TEST(RunFrames, ANewLidarExtrinsicGivesTheFramesOfARigWithIt) {
  // run --calibrate-online applied a new T_imu_lidar: the frames are those resolved from a dataset whose
  // LiDAR sits there.
  const Rig rig;
  Rig moved;
  moved.T_body_lidar = rig.T_body_lidar * Pose(0.05, -0.08, 0.1, 0.0, 0.0, 0.0);
  moved.description.streams[1].T_body_sensor = moved.T_body_lidar;
  const SE3 T_imu_lidar_new = moved.T_body_imu.inverse() * moved.T_body_lidar;
  for (TrajectoryFrame frame : {kLidar, kImu}) {
    RunFrames frames = Frames(rig, kLio, frame);
    frames.SetImuFromLidar(T_imu_lidar_new);
    const RunFrames expected = Frames(moved, kLio, frame);
    ExpectSame(*frames.T_imu_lidar, *expected.T_imu_lidar);
    ExpectSame(frames.T_output_body, expected.T_output_body);
    ExpectSame(frames.T_estimator_body, expected.T_estimator_body);
    ExpectSame(frames.T_map_world, expected.T_map_world);
  }
}

TEST(RunFrames, NamesReadBackAndAMissingExtrinsicIsAnError) {
  for (OdometryMode mode : {kLo, kLio}) EXPECT_EQ(ParseOdometryMode(Name(mode)), mode);
  for (TrajectoryFrame frame : {kLidar, kImu}) EXPECT_EQ(ParseTrajectoryFrame(Name(frame)), frame);
  for (MapSource source : {MapSource::kOdometry, MapSource::kTrajectory})
    EXPECT_EQ(ParseMapSource(Name(source)), source);
  EXPECT_FALSE(ParseTrajectoryFrame("camera"));
  Rig rig;
  rig.description.streams[1].T_body_sensor.reset();
  EXPECT_TRUE(ResolveRunFrames(rig.description, kLo, kLidar, MapSource::kOdometry).ok());
  EXPECT_NE(ResolveRunFrames(rig.description, kLo, kImu, MapSource::kOdometry)
                .error()
                .find("T_body_sensor of lidar"),
            std::string::npos);
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

// Stamps of the held-out views when `count` views (stamped 0, 1, ...) are split with `stride`.
std::vector<Stamp> HeldOutStamps(int count, int stride) {
  std::vector<StoredView> selected(count), train, test;
  for (int i = 0; i < count; ++i) selected[i].stamp = i;
  SplitHeldOut(std::move(selected), stride, train, test);
  EXPECT_EQ(train.size() + test.size(), static_cast<std::size_t>(count));
  for (std::size_t i = 1; i < train.size(); ++i) EXPECT_LT(train[i - 1].stamp, train[i].stamp);
  std::vector<Stamp> stamps;
  for (const StoredView& v : test) stamps.push_back(v.stamp);
  return stamps;
}

TEST(SplatCameraPoses, HeldOutViewsLieBetweenTrainingViews) {
  EXPECT_EQ(HeldOutStamps(25, 8), (std::vector<Stamp>{4, 12, 20}));  // KITTI drive 0009's 25 images
  EXPECT_EQ(HeldOutStamps(21, 8), (std::vector<Stamp>{4, 12}));      // 20 is the last: trained on
  EXPECT_EQ(HeldOutStamps(7, 2), (std::vector<Stamp>{1, 3, 5}));
  EXPECT_EQ(HeldOutStamps(6, 2), (std::vector<Stamp>{1, 3}));
  EXPECT_EQ(HeldOutStamps(5, 8), (std::vector<Stamp>{2}));  // too few for the rule: the middle one
  EXPECT_EQ(HeldOutStamps(3, 8), (std::vector<Stamp>{1}));
  EXPECT_TRUE(HeldOutStamps(2, 2).empty());  // the first and the last
  EXPECT_TRUE(HeldOutStamps(0, 8).empty());
}

TEST(SplatCameraPoses, CamerasThatCannotBePlacedAreErrorsThatSaySo) {
  Rig rig;
  rig.description.streams[2].camera_model.reset();
  EXPECT_NE(FindSplatCamera(rig.description, Frames(rig, kLio, kImu).T_output_body)
                .error()
                .find("cam0 has no intrinsics"),
            std::string::npos);
  rig = Rig();
  rig.description.streams[2].T_body_sensor.reset();
  EXPECT_NE(
      FindSplatCamera(rig.description, Frames(rig, kLio, kImu).T_output_body).error().find("no extrinsic"),
      std::string::npos);
  rig.description.streams.pop_back();
  EXPECT_NE(FindSplatCamera(rig.description, Frames(rig, kLio, kImu).T_output_body)
                .error()
                .find("no camera stream"),
            std::string::npos);
}

}  // namespace
}  // namespace uf::pipeline
