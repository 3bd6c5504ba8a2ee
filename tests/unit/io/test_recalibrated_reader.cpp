// dataset.calibration_file (odometry/io/recalibrated_reader.h) on a small dataset of the project's format:
// an IMU without extrinsic and a LiDAR with one, a scan between two IMU samples.
#include <gtest/gtest.h>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/folders/ultrafusion_dataset_writer.h"
#include "odometry/io/measurement_stream.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr Stamp kScanStamp = 1'700'000'000'100'000'000;

void WriteDataset(const fs::path& folder) {
  std::vector<StreamInfo> streams(2);
  streams[0].name = "/imu/data";
  streams[0].kind = SensorKind::kImu;
  streams[1].name = "/points";
  streams[1].kind = SensorKind::kLidar;
  streams[1].T_body_sensor = SE3(SO3::Exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.5, 1.0, -2));
  auto writer = UltrafusionDatasetWriter::Create(folder, streams);
  ASSERT_TRUE(writer.ok()) << writer.error();
  ImuSample imu;
  imu.stamp = kScanStamp - 50'000'000;
  imu.acc = {0, 0, 9.81};
  ImuSample later = imu;
  later.stamp = kScanStamp + 200'000'000;
  LidarScan scan;
  scan.stamp = kScanStamp;
  scan.end = kScanStamp + 100'000'000;
  scan.points = {{1.0f, 2.0f, 3.0f, 0.0f, 0, 0}};
  for (const Measurement& m : std::vector<Measurement>{{0, imu}, {1, scan}, {0, later}})
    ASSERT_TRUE(writer->Write(m).ok());
  const Status finished = writer->Finish();
  ASSERT_TRUE(finished.ok()) << finished.message();
}

// dataset.calibration_file: the file's sensors replace the extrinsic and shift the stamps of their streams
// (on top of the configured offsets); the others keep theirs; a sensor that names no stream, or the wrong
// kind, is an error naming the file and the sensor.
TEST(RecalibratedReader, ACalibrationFileReplacesTheDatasetsCalibration) {
  TempDir dir;
  WriteDataset(dir.path() / "sim");
  if (HasFatalFailure()) return;
  const SE3 T_new(SO3::Exp(Eigen::Vector3d(0.0, 0.05, 0.0)), Eigen::Vector3d(0.1, 0.2, 0.3));
  Calibration calibration;
  calibration.sensors.push_back({.name = "/points",
                                 .kind = SensorKind::kLidar,
                                 .T_body_sensor = T_new,
                                 .time_offset = -25'000'000,
                                 .camera_model = nullptr});
  const fs::path file = dir.path() / "calibration.yaml";
  ASSERT_TRUE(WriteCalibrationFile(file, calibration).ok());
  DatasetOptions options;
  options.calibration_file = file.string();
  auto reader = OpenDataset(dir.path() / "sim", options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  ASSERT_TRUE(description.streams[1].T_body_sensor);
  EXPECT_TRUE(description.streams[1].T_body_sensor->matrix().isApprox(T_new.matrix(), 1e-12));
  EXPECT_EQ(description.streams[1].time_offset, -25'000'000);
  EXPECT_EQ(description.streams[0].time_offset, 0);
  EXPECT_FALSE(description.streams[0].T_body_sensor);
  MeasurementStreamOptions stream_options;
  stream_options.time_offsets["lidar"] = 5'000'000;
  auto stream = MeasurementStream::Create(**reader, stream_options);
  ASSERT_TRUE(stream.ok()) << stream.error();
  EXPECT_EQ(stream->time_offset(1), -20'000'000);
  EXPECT_EQ(stream->time_offset(0), 0);
  Stamp read_scan = 0;
  while (true) {
    auto next = stream->Next();
    ASSERT_TRUE(next.ok()) << next.error();
    if (!*next) break;
    if ((*next)->stream == 1) read_scan = StampOf((*next)->data);
  }
  EXPECT_EQ(read_scan, kScanStamp - 20'000'000);

  auto open_error = [&](const std::string& name, SensorKind kind) {
    calibration.sensors[0].name = name;
    calibration.sensors[0].kind = kind;
    EXPECT_TRUE(WriteCalibrationFile(file, calibration).ok());
    auto opened = OpenDataset(dir.path() / "sim", options);
    return opened.ok() ? std::string() : opened.error();
  };
  EXPECT_NE(open_error("/velodyne", SensorKind::kLidar)
                .find("calibration.yaml: sensor '/velodyne' names no stream"),
            std::string::npos);
  EXPECT_NE(open_error("/points", SensorKind::kImu).find("sensor '/points' is a imu in the file and a lidar"),
            std::string::npos);
  options.calibration_file = (dir.path() / "missing.yaml").string();
  auto missing = OpenDataset(dir.path() / "sim", options);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("missing.yaml"), std::string::npos);
}

}  // namespace
}  // namespace uf
