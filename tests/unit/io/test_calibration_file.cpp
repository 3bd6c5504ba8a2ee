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

TEST(CameraIntrinsicsFile, RoundTripIsExactForBothModels) {
  TempDir dir;
  const PinholeRadtanIntrinsics radtan{
      {640, 480, 400.5, 401.25, 319.5, 239.75}, -0.1, 1.0 / 3.0, 1e-4, -2e-4, 0.001};
  ASSERT_TRUE(WriteCameraIntrinsicsFile(dir.File("radtan.yaml"), PinholeRadtan(radtan), "a header").ok());
  EXPECT_EQ(testing::ReadText(dir.File("radtan.yaml")).rfind("# a header\n", 0), 0u);
  auto read = ReadCameraIntrinsicsFile(dir.File("radtan.yaml"));
  ASSERT_TRUE(read.ok()) << read.error();
  const auto* camera = dynamic_cast<const PinholeRadtan*>(read->get());
  ASSERT_NE(camera, nullptr);
  EXPECT_EQ(camera->width(), 640);
  EXPECT_EQ(camera->height(), 480);
  const PinholeRadtanIntrinsics& k = camera->intrinsics();
  EXPECT_EQ(k.pinhole, radtan.pinhole);
  for (const auto& [got, want] : {std::pair{k.k1, radtan.k1},
                                  {k.k2, radtan.k2},
                                  {k.p1, radtan.p1},
                                  {k.p2, radtan.p2},
                                  {k.k3, radtan.k3}})
    EXPECT_EQ(got, want);

  const EquidistantIntrinsics fisheye{{640, 480, 300, 301, 320.5, 240.5}, 0.1, -0.01, 0.002, -0.0003};
  ASSERT_TRUE(WriteCameraIntrinsicsFile(dir.File("fisheye.yaml"), Equidistant(fisheye)).ok());
  read = ReadCameraIntrinsicsFile(dir.File("fisheye.yaml"));
  ASSERT_TRUE(read.ok()) << read.error();
  const auto* equidistant = dynamic_cast<const Equidistant*>(read->get());
  ASSERT_NE(equidistant, nullptr);
  EXPECT_EQ(equidistant->intrinsics().k4, -0.0003);
  EXPECT_EQ(equidistant->intrinsics().pinhole, fisheye.pinhole);
}

// `text` with the first `from` replaced by `to`.
std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  return text.replace(text.find(from), from.size(), to);
}

TEST(CameraIntrinsicsFile, ErrorsNameFileKeyLineAndValue) {
  TempDir dir;
  const std::string ok =
      "distortion_model: radial-tangential\nintrinsics: [50, 50, 31.5, 23.5]\n"
      "distortion_coefficients: [0, 0, 0, 0]\nresolution: [64, 48]\n";
  auto error = [&dir](const std::string& text) {
    auto read = ReadCameraIntrinsicsFile(dir.Write("c.yaml", text));
    return read.ok() ? std::string("<no error>") : read.error();
  };
  EXPECT_NE(error(ok + "fx: 1\n").find("c.yaml: fx (line 5): unknown key"), std::string::npos);
  EXPECT_NE(error("distortion_model: fov\n" + ok.substr(ok.find('\n') + 1))
                .find("c.yaml: distortion_model (line 1): 'fov' is not radial-tangential or equidistant"),
            std::string::npos);
  EXPECT_NE(
      error(Replaced(ok, "[50, 50, 31.5, 23.5]", "[50, x, 31.5, 23.5]"))
          .find("c.yaml: intrinsics (line 2): needs 4 numbers (fx, fy, cx, cy), found '[50, x, 31.5, 23.5]'"),
      std::string::npos);
  EXPECT_NE(error(Replaced(ok, "[0, 0, 0, 0]", "[0, 0, 0]"))
                .find("distortion_coefficients (line 3): needs 4 or 5 numbers"),
            std::string::npos);
  EXPECT_NE(error(Replaced(ok, "[64, 48]", "[64]")).find("resolution (line 4): needs 2 whole numbers"),
            std::string::npos);
  EXPECT_NE(error(Replaced(ok, "[64, 48]", "[64, 4]")).find("c.yaml: camera intrinsics: cy = 23.5"),
            std::string::npos);
  EXPECT_NE(error("intrinsics: [\n").find("c.yaml (line"), std::string::npos);
  EXPECT_NE(ReadCameraIntrinsicsFile(dir.File("none.yaml")).error().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace uf
