// The estimator's mode: names and their parsing, and what --mode (a name or auto) gets from datasets with
// and without IMU, wheel and GNSS streams and their extrinsics.
#include <gtest/gtest.h>

#include "viewer/pipeline/run/run_mode.h"

namespace uf::pipeline {
namespace {

StreamInfo Stream(std::string name, SensorKind kind, bool extrinsic = true) {
  StreamInfo stream;
  stream.name = std::move(name);
  stream.kind = kind;
  if (extrinsic) stream.T_body_sensor = SE3();
  return stream;
}

struct Dataset {
  DatasetDescription description;
  DatasetSensors sensors;
  explicit Dataset(std::vector<StreamInfo> streams) {
    description.path = "data";
    description.streams = std::move(streams);
    sensors = FindSensors(description);
  }
};

TEST(RunMode, NamesParseBack) {
  for (const std::string& name : ModeNames()) {
    Expected<std::optional<EstimatorMode>> mode = ParseMode(name);
    ASSERT_TRUE(mode.ok()) << mode.error();
    if (name == "auto") {
      EXPECT_FALSE(*mode);
    } else {
      EXPECT_EQ(ModeName(**mode), name);
    }
  }
  EXPECT_EQ(ModeName({OdometryMode::kLio, true, false}), "lwio");
  EXPECT_EQ(ModeName({OdometryMode::kLo, false, false}), "lo");
  EXPECT_EQ(ModeName({OdometryMode::kLio, false, true}), "lio+g");
  EXPECT_EQ(ModeName({OdometryMode::kLio, true, true}), "lwgio");
  EXPECT_EQ(**ParseMode("lwgio"), (EstimatorMode{OdometryMode::kLio, true, true}));
  EXPECT_EQ(ModeName({OdometryMode::kWio, true, false}), "wio");
  EXPECT_EQ(**ParseMode("wgio"), (EstimatorMode{OdometryMode::kWio, true, true}));
  EXPECT_NE(ParseMode("lo+g").error().find("needs the IMU"), std::string::npos);
  EXPECT_NE(ParseMode("lwgo").error().find("needs the IMU"), std::string::npos);
  EXPECT_EQ(ModeName({OdometryMode::kLio, false, false, true}), "lvio");
  EXPECT_EQ(ModeName({OdometryMode::kLio, true, false, true}), "lvwio");
  EXPECT_EQ(ModeName({OdometryMode::kLio, false, true, true}), "lvio+g");
  EXPECT_EQ(**ParseMode("lvwgio"), (EstimatorMode{OdometryMode::kLio, true, true, true}));
  EXPECT_NE(ParseMode("lvo").error().find("unknown mode"), std::string::npos);
}

TEST(RunMode, AutoPicksTheRichestTheDataSupports) {
  std::vector<std::string> notes;
  const Dataset all({Stream("lidar", SensorKind::kLidar), Stream("imu", SensorKind::kImu),
                     Stream("wheel", SensorKind::kWheel), Stream("gnss", SensorKind::kGnss)});
  EXPECT_EQ(*ChooseMode(std::nullopt, all.description, all.sensors, notes),
            (EstimatorMode{OdometryMode::kLio, true, true}));
  EXPECT_TRUE(notes.empty());

  const Dataset no_wheel_extrinsic({Stream("lidar", SensorKind::kLidar), Stream("imu", SensorKind::kImu),
                                    Stream("odom", SensorKind::kWheel, false)});
  EXPECT_EQ(*ChooseMode(std::nullopt, no_wheel_extrinsic.description, no_wheel_extrinsic.sensors, notes),
            (EstimatorMode{OdometryMode::kLio, false, false}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("ran lio (no wheel-to-IMU transform (T_body_sensor of odom), no GNSS stream)"),
            std::string::npos)
      << notes[0];

  notes.clear();
  const Dataset lidar_wheel({Stream("lidar", SensorKind::kLidar), Stream("wheel", SensorKind::kWheel)});
  EXPECT_EQ(*ChooseMode(std::nullopt, lidar_wheel.description, lidar_wheel.sensors, notes),
            (EstimatorMode{OdometryMode::kLo, false, false}));  // the factors need the inertial core
}

TEST(RunMode, WithoutALidarAutoRunsTheWheelInertialWindow) {
  std::vector<std::string> notes;
  const Dataset husky({Stream("imu", SensorKind::kImu), Stream("odom", SensorKind::kWheel),
                       Stream("fix", SensorKind::kGnss, false)});
  EXPECT_EQ(*ChooseMode(std::nullopt, husky.description, husky.sensors, notes),
            (EstimatorMode{OdometryMode::kWio, true, true}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("ran wgio (no LiDAR stream, no camera stream with intrinsics)"), std::string::npos)
      << notes[0];

  notes.clear();
  const Dataset no_gnss({Stream("imu", SensorKind::kImu), Stream("odom", SensorKind::kWheel)});
  EXPECT_EQ(*ChooseMode(std::nullopt, no_gnss.description, no_gnss.sensors, notes),
            (EstimatorMode{OdometryMode::kWio, true, false}));
  EXPECT_NE(notes[0].find("ran wio (no LiDAR stream, no camera stream with intrinsics, no GNSS stream)"),
            std::string::npos)
      << notes[0];

  // The wheel's extrinsic is needed; the LiDAR modes are named as what does not run either.
  const Dataset no_extrinsic({Stream("imu", SensorKind::kImu), Stream("odom", SensorKind::kWheel, false)});
  const Expected<EstimatorMode> none =
      ChooseMode(std::nullopt, no_extrinsic.description, no_extrinsic.sensors, notes);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(
      none.error().find("data: no LiDAR stream (for lo and lio) and no wheel-to-IMU transform (T_body_sensor "
                        "of odom) (for wio), no camera stream with intrinsics (for vio)"),
      std::string::npos)
      << none.error();
  const Expected<EstimatorMode> lio =
      ChooseMode(EstimatorMode{OdometryMode::kLio, false, false}, husky.description, husky.sensors, notes);
  ASSERT_FALSE(lio.ok());
  EXPECT_NE(lio.error().find("--mode lio: data has no LiDAR stream"), std::string::npos) << lio.error();
}

// A camera stream with intrinsics (a pinhole 640 x 480).
StreamInfo Camera(std::string name, bool extrinsic = true) {
  StreamInfo stream = Stream(std::move(name), SensorKind::kCamera, extrinsic);
  stream.camera_model =
      std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{640, 480, 400, 400, 319.5, 239.5}});
  return stream;
}

TEST(RunMode, WithoutALidarAutoAddsTheCamera) {
  std::vector<std::string> notes;
  const Dataset euroc({Stream("imu0", SensorKind::kImu), Camera("cam0")});
  EXPECT_EQ(*ChooseMode(std::nullopt, euroc.description, euroc.sensors, notes),
            (EstimatorMode{OdometryMode::kWio, false, false, true}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("ran vio (no LiDAR stream, no wheel odometry stream, no GNSS stream)"),
            std::string::npos)
      << notes[0];
  notes.clear();
  const Dataset all({Stream("imu", SensorKind::kImu), Stream("odom", SensorKind::kWheel), Camera("cam"),
                     Stream("fix", SensorKind::kGnss)});
  EXPECT_EQ(*ChooseMode(std::nullopt, all.description, all.sensors, notes),
            (EstimatorMode{OdometryMode::kWio, true, true, true}));
  EXPECT_EQ(ModeName(*ChooseMode(std::nullopt, all.description, all.sensors, notes)), "vwgio");
  // A camera without its extrinsic, or without intrinsics, is no camera for the estimator.
  const Dataset no_extrinsic({Stream("imu", SensorKind::kImu), Camera("cam", false)});
  const Expected<EstimatorMode> vio =
      ChooseMode(**ParseMode("vio"), no_extrinsic.description, no_extrinsic.sensors, notes);
  ASSERT_FALSE(vio.ok());
  EXPECT_NE(vio.error().find("--mode vio: data has no camera-to-IMU transform (T_body_sensor of cam)"),
            std::string::npos)
      << vio.error();
  const Dataset no_intrinsics({Stream("imu", SensorKind::kImu), Stream("cam", SensorKind::kCamera)});
  const Expected<EstimatorMode> vwio =
      ChooseMode(**ParseMode("vwio"), no_intrinsics.description, no_intrinsics.sensors, notes);
  ASSERT_FALSE(vwio.ok());
  EXPECT_NE(vwio.error().find("no wheel odometry stream, no camera stream with intrinsics"),
            std::string::npos)
      << vwio.error();
}

TEST(RunMode, LidarModesTakeTheCameraOnRequest) {
  std::vector<std::string> notes;
  const Dataset kitti(
      {Stream("velodyne", SensorKind::kLidar), Stream("oxts", SensorKind::kImu), Camera("image_02")});
  // Auto keeps LIO (the camera's factors are asked for by name: docs/METHOD.md "LiDAR-visual-inertial
  // odometry").
  EXPECT_EQ(*ChooseMode(std::nullopt, kitti.description, kitti.sensors, notes),
            (EstimatorMode{OdometryMode::kLio, false, false}));
  EXPECT_EQ(*ChooseMode(**ParseMode("lvio"), kitti.description, kitti.sensors, notes),
            (EstimatorMode{OdometryMode::kLio, false, false, true}));
  const Dataset no_camera({Stream("velodyne", SensorKind::kLidar), Stream("oxts", SensorKind::kImu)});
  const Expected<EstimatorMode> lvio =
      ChooseMode(**ParseMode("lvio"), no_camera.description, no_camera.sensors, notes);
  ASSERT_FALSE(lvio.ok());
  EXPECT_NE(lvio.error().find("--mode lvio: data has no camera stream with intrinsics"), std::string::npos)
      << lvio.error();
}

TEST(RunMode, AnExplicitModeNamesWhatIsMissing) {
  std::vector<std::string> notes;
  const Dataset lio({Stream("lidar", SensorKind::kLidar), Stream("imu", SensorKind::kImu)});
  const Expected<EstimatorMode> lwio =
      ChooseMode(EstimatorMode{OdometryMode::kLio, true}, lio.description, lio.sensors, notes);
  ASSERT_FALSE(lwio.ok());
  EXPECT_NE(
      lwio.error().find("--mode lwio: data has no wheel odometry stream (streams: lidar (lidar), imu (imu))"),
      std::string::npos)
      << lwio.error();
  const Expected<EstimatorMode> lwgio =
      ChooseMode(EstimatorMode{OdometryMode::kLio, true, true}, lio.description, lio.sensors, notes);
  ASSERT_FALSE(lwgio.ok());
  EXPECT_NE(lwgio.error().find("--mode lwgio: data has no wheel odometry stream, no GNSS stream"),
            std::string::npos)
      << lwgio.error();
  const Dataset lidar_wheel({Stream("lidar", SensorKind::kLidar), Stream("wheel", SensorKind::kWheel)});
  EXPECT_TRUE(
      ChooseMode(EstimatorMode{OdometryMode::kLo, true}, lidar_wheel.description, lidar_wheel.sensors, notes)
          .ok());
}

}  // namespace
}  // namespace uf::pipeline
