// A run's camera at any time (run/run_camera_poses.h) against hand-computed poses: the midpoint of two
// poses, exact stamps, the extrinsics composed in order, stamps out of the trajectory's span. cameras.yaml
// (run/run_cameras.h) written and read back exactly, and what `render RUN_DIR --stamps` reads from a run
// folder (run_render_inputs.h), with its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"
#include "viewer/pipeline/run/run_camera_poses.h"
#include "viewer/pipeline/run/run_cameras.h"
#include "viewer/pipeline/run/run_record.h"
#include "viewer/pipeline/run_render_inputs.h"

namespace uf::pipeline {
namespace {

using testing::TempDir;

SE3 Translation(double x, double y, double z) { return SE3(SO3(), Eigen::Vector3d(x, y, z)); }

SE3 AboutZ(double degrees, const Eigen::Vector3d& t) {
  return SE3(
      SO3(Eigen::Quaterniond(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()))),
      t);
}

// `pose` is the turn about z by `degrees_about_z` at `t`, to `tolerance` (m, and per rotation matrix entry).
void ExpectPose(const SE3& pose, double degrees_about_z, const Eigen::Vector3d& t, double tolerance = 1e-12) {
  EXPECT_LT((pose.translation() - t).norm(), tolerance) << pose.translation().transpose();
  const Eigen::Matrix3d expected = AboutZ(degrees_about_z, t).rotation();
  EXPECT_LT((pose.rotation() - expected).cwiseAbs().maxCoeff(), tolerance) << pose.matrix();
}

// t = 1 s: at the origin; t = 3 s: 2 m along x, turned 90 degrees about z.
Trajectory TwoPoses() {
  Trajectory trajectory;
  trajectory.stamps = {1'000'000'000, 3'000'000'000};
  trajectory.poses = {SE3(), AboutZ(90, Eigen::Vector3d(2, 0, 0))};
  return trajectory;
}

TEST(CameraPosesAt, InterpolatesHalfWayAndHitsTheStampsExactly) {
  const std::vector<Stamp> stamps = {2'000'000'000, 1'000'000'000, 3'000'000'000, 2'000'000'000};
  Expected<std::vector<SE3>> poses = CameraPosesAt(TwoPoses(), {}, stamps, "trajectory.tum", "stamps.txt");
  ASSERT_TRUE(poses.ok()) << poses.error();
  ASSERT_EQ(poses->size(), 4u);  // one per stamp, in the order given, repeats included
  ExpectPose((*poses)[0], 45, Eigen::Vector3d(1, 0, 0));  // slerp half way, lerp half way
  ExpectPose((*poses)[1], 0, Eigen::Vector3d(0, 0, 0));
  ExpectPose((*poses)[2], 90, Eigen::Vector3d(2, 0, 0));
  EXPECT_EQ((*poses)[3].matrix(), (*poses)[0].matrix());
  // A quarter of the way: 22.5 degrees, 0.5 m.
  const std::vector<Stamp> quarter = {1'500'000'000};
  poses = CameraPosesAt(TwoPoses(), {}, quarter, "trajectory.tum", "stamps.txt");
  ASSERT_TRUE(poses.ok());
  ExpectPose(poses->front(), 22.5, Eigen::Vector3d(0.5, 0, 0));
}

TEST(CameraPosesAt, ComposesMapWorldTrajectoryAndExtrinsicInOrder) {
  // T_M_C = T_M_W * T_W_F(t) * T_F_C with T_M_W 10 m along x, T_F_C 1 m along the frame's z, at the
  // midpoint (45 degrees, 1 m along x): (10, 0, 0) + (1, 0, 0) + R(45) (0, 0, 1) = (11, 0, 1).
  const CameraPlacement placement{.T_map_world = Translation(10, 0, 0),
                                  .T_frame_camera = Translation(0, 0, 1)};
  const std::vector<Stamp> stamps = {2'000'000'000, 3'000'000'000};
  Expected<std::vector<SE3>> poses = CameraPosesAt(TwoPoses(), placement, stamps, "t.tum", "s.txt");
  ASSERT_TRUE(poses.ok()) << poses.error();
  ExpectPose((*poses)[0], 45, Eigen::Vector3d(11, 0, 1));
  ExpectPose((*poses)[1], 90, Eigen::Vector3d(12, 0, 1));
  // An offset along the frame's x turns with the frame: at 3 s, R(90) (1, 0, 0) = (0, 1, 0).
  const CameraPlacement lever{.T_map_world = SE3(), .T_frame_camera = Translation(1, 0, 0)};
  poses = CameraPosesAt(TwoPoses(), lever, std::vector<Stamp>{3'000'000'000}, "t.tum", "s.txt");
  ASSERT_TRUE(poses.ok());
  ExpectPose(poses->front(), 90, Eigen::Vector3d(2, 1, 0));
}

TEST(CameraPosesAt, AStampOutsideTheSpanIsAnErrorNamingStampFileAndSpan) {
  for (Stamp outside : {Stamp{999'999'999}, Stamp{3'000'000'001}}) {
    const std::vector<Stamp> stamps = {2'000'000'000, outside};
    Expected<std::vector<SE3>> poses =
        CameraPosesAt(TwoPoses(), {}, stamps, "run/trajectory.tum", "stamps.txt");
    ASSERT_FALSE(poses.ok());
    for (const std::string& part :
         {"stamps.txt: stamp " + FormatSeconds(outside) + " s (" + std::to_string(outside) + " ns)",
          std::string("run/trajectory.tum, [1.000000000, 3.000000000] s")})
      EXPECT_NE(poses.error().find(part), std::string::npos) << part << "\n" << poses.error();
  }
}

// A dataset with an IMU, two placeable cameras and one without an extrinsic.
DatasetDescription ThreeCameras() {
  DatasetDescription description;
  StreamInfo imu, left, right, loose;
  imu.name = "imu", imu.kind = SensorKind::kImu, imu.T_body_sensor = SE3();
  Vector6d xi;
  xi << 0.1, -0.05, 0.2, -1.5, 0.02, -1.6;
  left.name = "cam_left", left.kind = SensorKind::kCamera, left.T_body_sensor = SE3::Exp(xi);
  left.camera_model = std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{64, 48, 50, 50, 31.5, 23.5}});
  right = left;
  right.name = "cam_right", right.T_body_sensor = SE3::Exp(-xi);
  right.camera_model =
      std::make_shared<Equidistant>(EquidistantIntrinsics{{80, 60, 40, 40, 39.5, 29.5}, 0.1, 0, 0, 0});
  loose = left;
  loose.name = "cam_loose", loose.T_body_sensor.reset();
  description.streams = {imu, left, loose, right};
  return description;
}

TEST(RunCameras, CamerasYamlRoundTripsExactlyAndACameraIsFoundByName) {
  TempDir dir;
  const DatasetDescription description = ThreeCameras();
  const Calibration cameras = PlacedCameras(description, {0, -25'000'000, 0, 0});
  ASSERT_EQ(cameras.sensors.size(), 2u);  // cam_loose cannot be placed
  EXPECT_EQ(cameras.sensors[0].time_offset, -25'000'000);
  ASSERT_TRUE(WriteRunCameras(dir.path(), cameras).ok());
  Expected<Calibration> read = ReadRunCameras(dir.path());
  ASSERT_TRUE(read.ok()) << read.error();

  Expected<SensorCalibration> first = FindRunCamera(*read, "", dir.path());
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first->name, "cam_left");
  EXPECT_EQ(first->time_offset, -25'000'000);
  // Bit for bit: the views are placed with it.
  EXPECT_EQ(first->T_body_sensor.matrix(), description.streams[1].T_body_sensor->matrix());
  Expected<SensorCalibration> right = FindRunCamera(*read, "cam_right", dir.path());
  ASSERT_TRUE(right.ok()) << right.error();
  EXPECT_EQ(right->T_body_sensor.matrix(), description.streams[3].T_body_sensor->matrix());
  ASSERT_NE(dynamic_cast<const Equidistant*>(right->camera_model.get()), nullptr);
  EXPECT_EQ(right->camera_model->width(), 80);

  Expected<SensorCalibration> unknown = FindRunCamera(*read, "cam_loose", dir.path());
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().find("--camera cam_loose: no such camera in"), std::string::npos)
      << unknown.error();
  EXPECT_NE(unknown.error().find("(cameras: cam_left, cam_right)"), std::string::npos) << unknown.error();

  // No camera to place: no file (an older one goes), and reading says why there may be none.
  ASSERT_TRUE(WriteRunCameras(dir.path(), PlacedCameras(DatasetDescription{}, {})).ok());
  Expected<Calibration> none = ReadRunCameras(dir.path());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().find("cameras.yaml: missing"), std::string::npos) << none.error();
}

TEST(RunRenderInputs, PlacesTheChosenCameraOnTheTrajectoryWithTheRunsFrames) {
  TempDir dir;
  const std::string stamps = dir.Write("stamps.txt", "# mid-way, then the last pose\n2.0\n3 # end\n");
  RunRecord record;
  record.dataset = "/data/seq";
  record.frames.mode = OdometryMode::kLio, record.frames.trajectory_frame = TrajectoryFrame::kImu;
  record.frames.T_imu_lidar = SE3();
  record.frames.T_output_body = Translation(0, 0, 0.5);  // T_F_B
  record.frames.T_map_world = Translation(10, 0, 0);     // T_M_W
  ASSERT_TRUE(WriteRunRecord(dir.path(), record).ok());

  // Each missing piece is named, in the order they are read.
  Expected<RenderInputs> inputs = ReadRunRenderInputs(dir.path(), stamps, "");
  ASSERT_FALSE(inputs.ok());
  EXPECT_NE(inputs.error().find("splats.ply: missing; the run trained no splats"), std::string::npos)
      << inputs.error();
  dir.Write("splats.ply", "");  // only its presence is checked here
  inputs = ReadRunRenderInputs(dir.path(), stamps, "");
  ASSERT_FALSE(inputs.ok());
  EXPECT_NE(inputs.error().find("cameras.yaml: missing"), std::string::npos) << inputs.error();
  Calibration cameras = PlacedCameras(ThreeCameras(), {});
  cameras.sensors[1].T_body_sensor = Translation(1, 0, 0);  // T_B_C of cam_right
  ASSERT_TRUE(WriteRunCameras(dir.path(), cameras).ok());
  inputs = ReadRunRenderInputs(dir.path(), stamps, "cam_right");
  ASSERT_FALSE(inputs.ok());
  EXPECT_NE(inputs.error().find("trajectory.tum: missing"), std::string::npos) << inputs.error();
  ASSERT_TRUE(WriteTumTrajectory(dir.File("trajectory.tum"), TwoPoses()).ok());

  inputs = ReadRunRenderInputs(dir.path(), stamps, "cam_right");
  ASSERT_TRUE(inputs.ok()) << inputs.error();
  EXPECT_EQ(inputs->camera_name, "cam_right");
  EXPECT_EQ(inputs->camera->width(), 80);
  EXPECT_EQ(inputs->splats, dir.path() / "splats.ply");
  EXPECT_EQ(inputs->stamps, (std::vector<Stamp>{2'000'000'000, 3'000'000'000}));
  // T_M_C = T_M_W T_W_F(t) T_F_B T_B_C: (10, 0, 0) + (1, 0, 0) + R(45) ((0, 0, 0.5) + (1, 0, 0)) mid-way,
  // (10, 0, 0) + (2, 0, 0) + R(90) (1, 0, 0.5) at the end.
  ASSERT_EQ(inputs->T_world_camera.size(), 2u);
  // trajectory.tum holds nanometres and quaternions to 1e-12.
  ExpectPose(inputs->T_world_camera[0], 45, Eigen::Vector3d(11 + std::sqrt(0.5), std::sqrt(0.5), 0.5), 1e-9);
  ExpectPose(inputs->T_world_camera[1], 90, Eigen::Vector3d(12, 1, 0.5), 1e-9);

  const std::string late = dir.Write("late.txt", "2.5\n3.5\n");
  inputs = ReadRunRenderInputs(dir.path(), late, "");
  ASSERT_FALSE(inputs.ok());
  EXPECT_NE(inputs.error().find("late.txt: stamp 3.500000000 s"), std::string::npos) << inputs.error();
  const std::string bad = dir.Write("bad.txt", "2.5\nabc\n");
  inputs = ReadRunRenderInputs(dir.path(), bad, "");
  ASSERT_FALSE(inputs.ok());
  EXPECT_NE(inputs.error().find("bad.txt:2: time (column 1) is not a time in seconds: 'abc'"),
            std::string::npos)
      << inputs.error();
}

}  // namespace
}  // namespace uf::pipeline
