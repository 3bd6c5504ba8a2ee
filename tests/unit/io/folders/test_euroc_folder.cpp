// EuRoC ASL folders made by the test: merge order, sensor.yaml calibration, images, damaged files.
#include <gtest/gtest.h>

#include "odometry/io/folders/folder_readers.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/folders/folder_fixtures.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr const char* kImuYaml = R"(# General sensor definitions.
sensor_type: imu
comment: VI-Sensor IMU (ADIS16448)
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, 0.0,
         0.0, 1.0, 0.0, 0.0,
         0.0, 0.0, 1.0, 0.0,
         0.0, 0.0, 0.0, 1.0]
rate_hz: 200
gyroscope_noise_density: 1.6968e-04
)";

constexpr const char* kCamYaml = R"(%YAML:1.0
sensor_type: camera
T_BS:
  cols: 4
  rows: 4
  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
         0.0, 0.0, 0.0, 1.0]
rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375]
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
)";

// mav0 with imu0 (4 samples, 5 ms apart), cam0 and cam1 (2 frames each), ground truth.
fs::path MakeEuroc(const TempDir& dir) {
  const fs::path mav = dir.path() / "mav0";
  for (const char* sensor : {"imu0", "cam0/data", "cam1/data", "state_groundtruth_estimate0"})
    fs::create_directories(mav / sensor);
  testing::WriteBytes(mav / "imu0" / "data.csv",
                      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
                      "1403636579758555392,-0.099134701513277898,0.14730578886832138,0.02722713633111154,"
                      "8.1476917083333333,-0.37592158333333331,-2.4026292499999999\n"
                      "1403636579763555584,0.1,0.2,0.3,0.4,0.5,0.6\n"
                      "1403636579768555520,1,2,3,4,5,6\n"
                      "1403636579773555456,1,2,3,4,5,6\n");
  testing::WriteBytes(mav / "imu0" / "sensor.yaml", kImuYaml);
  for (const char* cam : {"cam0", "cam1"}) {
    testing::WriteBytes(mav / cam / "data.csv",
                        "#timestamp [ns],filename\n1403636579763555584,1403636579763555584.png\n"
                        "1403636579773555456,1403636579773555456.png\n");
    testing::WriteBytes(mav / cam / "data" / "1403636579763555584.png", testing::PngBytes());
    testing::WriteBytes(mav / cam / "data" / "1403636579773555456.png", testing::PngBytes(4, 4, 3));
    testing::WriteBytes(mav / cam / "sensor.yaml", kCamYaml);
  }
  testing::WriteBytes(
      mav / "state_groundtruth_estimate0" / "data.csv",
      "#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
      "1403636579758555392,4.688319,-1.786938,0.783338,0.534108,-0.153029,-0.827383,-0.082152\n");
  return mav;
}

// (stream, stamp) of every measurement, in delivery order.
std::vector<std::pair<int, Stamp>> Order(DatasetReader& reader) {
  std::vector<std::pair<int, Stamp>> order;
  while (true) {
    auto next = reader.Next();
    EXPECT_TRUE(next.ok()) << next.error();
    if (!next.ok() || !*next) break;
    order.emplace_back((*next)->stream, StampOf((*next)->data));
  }
  return order;
}

TEST(EurocFolder, DescribesStreamsWithCalibration) {
  TempDir dir;
  const fs::path mav = MakeEuroc(dir);
  for (const fs::path& path : {dir.path(), mav}) {  // the root or mav0 itself
    auto reader = OpenEurocFolder(path);
    ASSERT_TRUE(reader.ok()) << reader.error();
    const DatasetDescription& description = (*reader)->description();
    ASSERT_EQ(description.streams.size(), 3u);
    EXPECT_EQ(description.streams[0].kind, SensorKind::kImu);
    EXPECT_EQ(description.streams[1].kind, SensorKind::kCamera);
    EXPECT_EQ(description.streams[1].camera, 0);
    EXPECT_EQ(description.streams[2].camera, 1);
    EXPECT_EQ(description.streams[0].nominal_rate_hz, 200);
    EXPECT_EQ(description.streams[1].nominal_rate_hz, 20);
    ASSERT_TRUE(description.streams[1].T_body_sensor);
    EXPECT_DOUBLE_EQ(description.streams[1].T_body_sensor->translation().y(), -0.064676986768);
    EXPECT_DOUBLE_EQ(description.streams[1].T_body_sensor->rotation()(0, 1), -0.999880929698);
    EXPECT_EQ(description.streams[0].camera_model, nullptr);
    const auto* camera = dynamic_cast<const PinholeRadtan*>(description.streams[1].camera_model.get());
    ASSERT_NE(camera, nullptr);
    EXPECT_EQ(camera->width(), 752);
    EXPECT_EQ(camera->height(), 480);
    EXPECT_EQ(camera->intrinsics().pinhole.fx, 458.654);
    EXPECT_EQ(camera->intrinsics().pinhole.cy, 248.375);
    EXPECT_EQ(camera->intrinsics().k1, -0.28340811);
    EXPECT_EQ(camera->intrinsics().p2, 1.76187114e-05);
    EXPECT_EQ(camera->intrinsics().k3, 0);
    ASSERT_TRUE(description.ground_truth);
    EXPECT_EQ(*description.ground_truth, mav / "state_groundtruth_estimate0" / "data.csv");
  }
  auto reader = OpenEurocFolder(dir.path());
  EXPECT_EQ((*reader)->description().streams[0].name, "mav0/imu0/data.csv");
}

TEST(EurocFolder, MergesStreamsByStampWithImagesAsPngBytes) {
  TempDir dir;
  MakeEuroc(dir);
  auto reader = OpenEurocFolder(dir.path());
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto first = (*reader)->Next();
  ASSERT_TRUE(first.ok() && *first);
  const ImuSample& imu = std::get<ImuSample>((*first)->data);
  EXPECT_EQ(imu.stamp, 1403636579758555392);
  EXPECT_EQ(imu.gyro.x(), -0.099134701513277898);
  EXPECT_EQ(imu.acc.z(), -2.4026292499999999);
  auto second = (*reader)->Next();  // equal stamps: the lower stream (imu) first, then cam0, cam1
  ASSERT_TRUE(second.ok() && *second);
  EXPECT_EQ((*second)->stream, 0);
  auto frame_measurement = (*reader)->Next();
  ASSERT_TRUE(frame_measurement.ok() && *frame_measurement);
  const CameraFrame& frame = std::get<CameraFrame>((*frame_measurement)->data);
  EXPECT_EQ(frame.camera, 0);
  EXPECT_EQ(frame.encoded.format, "png");
  EXPECT_EQ(std::string(frame.encoded.bytes.begin(), frame.encoded.bytes.end()), testing::PngBytes());
  EXPECT_TRUE(frame.image.empty());

  auto again = OpenEurocFolder(dir.path());
  const std::vector<std::pair<int, Stamp>> expected = {
      {0, 1403636579758555392}, {0, 1403636579763555584}, {1, 1403636579763555584}, {2, 1403636579763555584},
      {0, 1403636579768555520}, {0, 1403636579773555456}, {1, 1403636579773555456}, {2, 1403636579773555456}};
  EXPECT_EQ(Order(**again), expected);
}

TEST(EurocFolder, SkipsMissingImagesWithAWarning) {
  TempDir dir;
  const fs::path mav = MakeEuroc(dir);
  fs::remove(mav / "cam1" / "data" / "1403636579763555584.png");
  testing::WriteBytes(mav / "cam1" / "data" / "1403636579773555456.png", "not an image");
  auto reader = OpenEurocFolder(dir.path());
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ(Order(**reader).size(), 6u);
  const ReadWarning* missing = testing::FindWarning(**reader, "missing");
  ASSERT_NE(missing, nullptr);
  EXPECT_EQ(missing->count, 1);
  EXPECT_EQ(missing->stream, "mav0/cam1/data.csv");
  EXPECT_NE(missing->what.find("1403636579763555584.png"), std::string::npos);
  ASSERT_NE(testing::FindWarning(**reader, "not a PNG or JPEG"), nullptr);
}

TEST(EurocFolder, DamagedFilesGiveNamedErrors) {
  {
    TempDir dir;
    const fs::path mav = MakeEuroc(dir);
    testing::WriteBytes(mav / "imu0" / "data.csv",
                        "#header\n1403636579758555392,1,2,3,4,5,6\n1403636579763555584,1,2,x,4,5,6\n");
    auto reader = OpenEurocFolder(dir.path());
    ASSERT_TRUE(reader.ok()) << reader.error();
    // The first sample is delivered, then the damaged line is reported.
    ASSERT_TRUE((*reader)->Next().ok());
    Expected<std::optional<Measurement>> next = std::optional<Measurement>();
    for (int i = 0; i < 8 && next.ok(); ++i) next = (*reader)->Next();
    ASSERT_FALSE(next.ok());
    EXPECT_NE(next.error().find("imu0/data.csv:3: gyro z (column 4) is not a number: 'x'"), std::string::npos)
        << next.error();
  }
  {
    TempDir dir;
    const fs::path mav = MakeEuroc(dir);
    testing::WriteBytes(mav / "imu0" / "data.csv", "1403636579758555392,1,2,3,4,5\n");
    auto reader = OpenEurocFolder(dir.path());
    ASSERT_FALSE(reader.ok());
    EXPECT_NE(
        reader.error().find("data.csv:1: expected 7 columns (stamp_ns, gx, gy, gz, ax, ay, az), found 6"),
        std::string::npos);
  }
  {
    TempDir dir;
    const fs::path mav = MakeEuroc(dir);
    testing::WriteBytes(mav / "cam0" / "data.csv", "20,a.png\n10,b.png\n");
    auto reader = OpenEurocFolder(dir.path());
    ASSERT_TRUE(reader.ok());
    Expected<std::optional<Measurement>> next = std::optional<Measurement>();
    for (int i = 0; i < 10 && next.ok(); ++i) next = (*reader)->Next();
    ASSERT_FALSE(next.ok());
    EXPECT_NE(next.error().find("cam0/data.csv:2: stamp 10 ns is not after the previous stamp 20 ns"),
              std::string::npos)
        << next.error();
  }
  {
    TempDir dir;
    const fs::path mav = MakeEuroc(dir);
    fs::remove(mav / "cam1" / "data.csv");
    EXPECT_NE(OpenEurocFolder(dir.path()).error().find("cam1/data.csv: missing"), std::string::npos);
  }
  {
    TempDir dir;
    const fs::path mav = MakeEuroc(dir);
    testing::WriteBytes(mav / "cam0" / "sensor.yaml", "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 2, 3]\n");
    EXPECT_NE(OpenEurocFolder(dir.path())
                  .error()
                  .find("sensor.yaml: T_BS: a 4x4 transform needs 16 numbers, found 3"),
              std::string::npos);
    std::string fisheye_lens(kCamYaml);
    fisheye_lens.replace(fisheye_lens.find("radial-tangential"), 17, "fov");
    testing::WriteBytes(mav / "cam0" / "sensor.yaml", fisheye_lens);
    EXPECT_NE(OpenEurocFolder(dir.path())
                  .error()
                  .find("cam0/sensor.yaml: distortion_model (line 14): 'fov' is not"),
              std::string::npos);
    std::string off_centre(kCamYaml);
    off_centre.replace(off_centre.find("367.215"), 7, "900.000");
    testing::WriteBytes(mav / "cam0" / "sensor.yaml", off_centre);
    EXPECT_NE(OpenEurocFolder(dir.path()).error().find("cam0/sensor.yaml: "), std::string::npos);
    EXPECT_NE(OpenEurocFolder(dir.path()).error().find("900"), std::string::npos);
    testing::WriteBytes(mav / "cam0" / "sensor.yaml", "T_BS: [unclosed\n");
    EXPECT_NE(OpenEurocFolder(dir.path()).error().find("cam0/sensor.yaml: "), std::string::npos);
  }
  {
    TempDir dir;
    EXPECT_NE(OpenEurocFolder(dir.path()).error().find("no imuN/ or camN/ sensor folders"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace uf
