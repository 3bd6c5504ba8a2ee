#include <gtest/gtest.h>

#include "odometry/io/calibration_file.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

using testing::TempDir;

Calibration TwoSensors() {
  Calibration calibration;
  SensorCalibration lidar;
  lidar.name = "lidar";
  lidar.kind = SensorKind::kLidar;
  lidar.T_body_sensor = SE3(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(0.1, -0.2, 0.3));
  lidar.time_offset = -123'456'789;
  calibration.sensors.push_back(lidar);
  SensorCalibration camera;
  camera.name = "cam0";
  camera.kind = SensorKind::kCamera;
  camera.T_body_sensor = SE3(SO3::Exp(Eigen::Vector3d(-1.2, 0.0, -1.5)), Eigen::Vector3d(0.5, 0.0, 1e-3));
  PinholeRadtanIntrinsics k{{640, 480, 400.5, 401.25, 319.5, 239.75}, -0.1, 0.01, 1e-4, -2e-4, 0.0};
  camera.camera_model = std::make_shared<PinholeRadtan>(k);
  calibration.sensors.push_back(camera);
  return calibration;
}

TEST(CalibrationFile, RoundTripIsExact) {
  TempDir dir;
  const Calibration written = TwoSensors();
  ASSERT_TRUE(WriteCalibrationFile(dir.File("c.yaml"), written, "line one\nline two").ok());
  EXPECT_EQ(testing::ReadText(dir.File("c.yaml")).rfind("# line one\n# line two\n", 0), 0u);
  auto read = ReadCalibrationFile(dir.File("c.yaml"));
  ASSERT_TRUE(read.ok()) << read.error();
  ASSERT_EQ(read->sensors.size(), 2u);
  EXPECT_EQ(read->body_frame, "imu");
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(read->sensors[i].name, written.sensors[i].name);
    EXPECT_EQ(read->sensors[i].kind, written.sensors[i].kind);
    EXPECT_EQ(read->sensors[i].time_offset, written.sensors[i].time_offset);
    // Written with shortest round-trip digits: the matrix comes back bit-exact.
    EXPECT_EQ(read->sensors[i].T_body_sensor.matrix(), written.sensors[i].T_body_sensor.matrix());
  }
  EXPECT_EQ(read->sensors[0].camera_model, nullptr);
  const auto* camera = dynamic_cast<const PinholeRadtan*>(read->sensors[1].camera_model.get());
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->intrinsics().pinhole.fy, 401.25);
  EXPECT_EQ(camera->intrinsics().p2, -2e-4);
  EXPECT_EQ(read->Find("cam0"), &read->sensors[1]);
  EXPECT_EQ(read->Find("nope"), nullptr);
}

std::string ReadError(const std::string& text) {
  TempDir dir;
  auto read = ReadCalibrationFile(dir.Write("c.yaml", text));
  return read.ok() ? std::string("<no error>") : read.error();
}

TEST(CalibrationFile, BadFilesNameFileKeyAndValue) {
  const std::string identity = "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]";
  const std::string sensor = "  sensors:\n    - {name: l, kind: lidar, T_body_sensor: " + identity;
  EXPECT_NE(ReadError("dataset: {}\n").find("c.yaml: no 'calibration:' section"), std::string::npos);
  EXPECT_NE(ReadError("calibration:\n  sensor: []\n").find("unknown key 'sensor'"), std::string::npos);
  EXPECT_NE(ReadError("calibration:\n" + sensor + ", colour: red}\n").find("sensors.0: unknown key 'colour'"),
            std::string::npos);
  EXPECT_NE(
      ReadError("calibration:\n  sensors:\n    - {name: l, kind: radar, T_body_sensor: " + identity + "}\n")
          .find("kind: 'radar' is not"),
      std::string::npos);
  EXPECT_NE(
      ReadError("calibration:\n" + sensor + ", time_offset_s: soon}\n").find("time_offset_s: not a number"),
      std::string::npos);
  EXPECT_NE(ReadError("calibration:\n" + sensor + "}\n" +
                      "    - {name: l, kind: imu, T_body_sensor: " + identity + "}\n")
                .find("sensors.1.name: 'l' appears twice"),
            std::string::npos);
  EXPECT_NE(ReadError("calibration:\n  sensors:\n    - {name: l, kind: lidar, T_body_sensor: "
                      "[2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}\n")
                .find("T_body_sensor"),
            std::string::npos);
  EXPECT_NE(
      ReadError("calibration:\n" + sensor + ", intrinsics: {}}\n").find("intrinsics: given for a lidar"),
      std::string::npos);
  EXPECT_NE(ReadError("calibration: [\n").find("c.yaml (line"), std::string::npos);
}

}  // namespace
}  // namespace uf
