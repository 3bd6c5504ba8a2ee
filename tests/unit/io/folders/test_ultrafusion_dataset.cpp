// The project's own dataset format: an exact round trip of every measurement kind, atomic writing, and
// damaged datasets.
#include <gtest/gtest.h>

#include "odometry/io/folders/folder_readers.h"
#include "odometry/io/folders/lidar_record_file.h"
#include "odometry/io/folders/ultrafusion_dataset_writer.h"
#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/folders/folder_fixtures.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

std::vector<StreamInfo> Streams() {
  std::vector<StreamInfo> streams(6);
  const SensorKind kinds[] = {SensorKind::kImu,   SensorKind::kLidar, SensorKind::kCamera,
                              SensorKind::kWheel, SensorKind::kGnss,  SensorKind::kCamera};
  const char* names[] = {"/imu/data", "/points", "/cam/left", "/odom", "/fix", "/cam/right"};
  for (int i = 0; i < 6; ++i) {
    streams[i].kind = kinds[i];
    streams[i].name = names[i];
  }
  streams[0].nominal_rate_hz = 200;
  streams[1].T_body_sensor =
      SE3(SO3::Exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.5, 1.0 / 3, -2));
  streams[5].camera = 3;
  streams[2].camera_model = std::make_shared<PinholeRadtan>(
      PinholeRadtanIntrinsics{{640, 480, 400.5, 401.25, 319.5, 239.75}, -0.28, 0.07, 1e-4, -2e-5, 0.01});
  streams[5].camera_model = std::make_shared<Equidistant>(
      EquidistantIntrinsics{{1280, 1024, 350, 350.5, 640.1, 511.9}, 0.1, -0.02, 3e-3, -1e-4});
  return streams;
}

// One of each kind, with values that need every digit (1/3, 0.1) to survive the round trip.
std::vector<Measurement> Measurements() {
  ImuSample imu;
  imu.stamp = 1'700'000'000'123'456'789;
  imu.gyro = {0.1, -1.0 / 3, 1e-300};
  imu.acc = {9.80665, -0.0, 2.5e10};
  ImuSample imu2 = imu;
  imu2.stamp += 1;
  LidarScan scan;
  scan.stamp = imu.stamp - 5;
  scan.end = scan.stamp + 100'000'000;
  scan.has_point_times = scan.has_ring = true;
  scan.points = {{0.1f, -2.5f, 1e-7f, 17.5f, 63, 99'999'999}, {-3.25f, 4, 5, 0, 0, 0}};
  LidarScan empty_scan;
  empty_scan.stamp = empty_scan.end = scan.stamp + 1'000'000'000;
  empty_scan.point_times_from_azimuth = true;
  CameraFrame png_frame;
  png_frame.stamp = imu.stamp + 10;
  const std::string png = testing::PngBytes(5, 3, 3);
  png_frame.encoded.format = "png";
  png_frame.encoded.bytes.assign(png.begin(), png.end());
  CameraFrame decoded_frame;  // written by encoding the decoded image to PNG
  decoded_frame.stamp = imu.stamp + 20;
  decoded_frame.camera = 3;
  decoded_frame.image = {2, 2, 3, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}};
  WheelSample wheel;
  wheel.stamp = imu.stamp + 7;
  wheel.linear_velocity = {1.5, 0.1, 0};
  wheel.angular_velocity = {0, 0, -0.7};
  GnssFix fix;
  fix.stamp = imu.stamp + 3;
  fix.latitude_deg = 42.36153720000001;
  fix.longitude_deg = -71.0917;
  fix.altitude_m = -12.3;
  fix.covariance_enu << 1, 0.1, 0.2, 0.1, 2, 0.3, 0.2, 0.3, 4;
  fix.status = GnssFixStatus::kRtkFloat;
  return {{0, imu},   {1, scan}, {0, imu2},          {2, png_frame},
          {3, wheel}, {4, fix},  {5, decoded_frame}, {1, empty_scan}};
}

void WriteDataset(const fs::path& folder) {
  auto writer = UltrafusionDatasetWriter::Create(folder, Streams());
  ASSERT_TRUE(writer.ok()) << writer.error();
  for (const Measurement& m : Measurements()) ASSERT_TRUE(writer->Write(m).ok());
  Trajectory ground_truth;
  ground_truth.stamps = {1'700'000'000'123'456'789, 1'700'000'000'223'456'789};
  ground_truth.poses = {SE3(), SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.5)), Eigen::Vector3d(1, 2, 3))};
  ASSERT_TRUE(writer->WriteGroundTruth(ground_truth).ok());
  Status finished = writer->Finish();
  ASSERT_TRUE(finished.ok()) << finished.message();
}

void ExpectEqual(const MeasurementData& read, const MeasurementData& written) {
  ASSERT_EQ(read.index(), written.index());
  if (const auto* imu = std::get_if<ImuSample>(&written)) {
    EXPECT_EQ(std::get<ImuSample>(read).stamp, imu->stamp);
    EXPECT_EQ(std::get<ImuSample>(read).gyro, imu->gyro);
    EXPECT_EQ(std::get<ImuSample>(read).acc, imu->acc);
  } else if (const auto* scan = std::get_if<LidarScan>(&written)) {
    const LidarScan& r = std::get<LidarScan>(read);
    EXPECT_EQ(r.stamp, scan->stamp);
    EXPECT_EQ(r.end, scan->end);
    EXPECT_EQ(r.has_point_times, scan->has_point_times);
    EXPECT_EQ(r.point_times_from_azimuth, scan->point_times_from_azimuth);
    EXPECT_EQ(r.has_ring, scan->has_ring);
    ASSERT_EQ(r.points.size(), scan->points.size());
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      EXPECT_EQ(r.points[i].x, scan->points[i].x);
      EXPECT_EQ(r.points[i].y, scan->points[i].y);
      EXPECT_EQ(r.points[i].z, scan->points[i].z);
      EXPECT_EQ(r.points[i].intensity, scan->points[i].intensity);
      EXPECT_EQ(r.points[i].ring, scan->points[i].ring);
      EXPECT_EQ(r.points[i].offset_ns, scan->points[i].offset_ns);
    }
  } else if (const auto* frame = std::get_if<CameraFrame>(&written)) {
    const CameraFrame& r = std::get<CameraFrame>(read);
    EXPECT_EQ(r.stamp, frame->stamp);
    EXPECT_EQ(r.encoded.format, "png");
    if (!frame->encoded.empty()) {
      EXPECT_EQ(r.encoded.bytes, frame->encoded.bytes);
    }
    EXPECT_FALSE(r.encoded.bytes.empty());
  } else if (const auto* wheel = std::get_if<WheelSample>(&written)) {
    EXPECT_EQ(std::get<WheelSample>(read).stamp, wheel->stamp);
    EXPECT_EQ(std::get<WheelSample>(read).linear_velocity, wheel->linear_velocity);
    EXPECT_EQ(std::get<WheelSample>(read).angular_velocity, wheel->angular_velocity);
  } else if (const auto* fix = std::get_if<GnssFix>(&written)) {
    const GnssFix& r = std::get<GnssFix>(read);
    EXPECT_EQ(r.stamp, fix->stamp);
    EXPECT_EQ(r.latitude_deg, fix->latitude_deg);
    EXPECT_EQ(r.longitude_deg, fix->longitude_deg);
    EXPECT_EQ(r.altitude_m, fix->altitude_m);
    EXPECT_EQ(r.covariance_enu, fix->covariance_enu);
    EXPECT_EQ(r.status, fix->status);
  }
}

TEST(UltrafusionDataset, RoundTripsEveryMeasurementKindExactly) {
  TempDir dir;
  WriteDataset(dir.path() / "sim");
  auto reader = OpenUltrafusionFolder(dir.path() / "sim");
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  ASSERT_EQ(description.streams.size(), 6u);
  const std::vector<StreamInfo> written = Streams();
  for (std::size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ(description.streams[i].name, written[i].name);
    EXPECT_EQ(description.streams[i].kind, written[i].kind);
  }
  EXPECT_EQ(description.streams[2].camera, 0);  // numbered in order when not given
  EXPECT_EQ(description.streams[5].camera, 3);
  EXPECT_EQ(description.streams[0].nominal_rate_hz, 200);
  ASSERT_TRUE(description.streams[1].T_body_sensor);
  EXPECT_EQ(description.streams[1].T_body_sensor->matrix(), written[1].T_body_sensor->matrix());
  // Camera calibrations come back exactly: same model, same numbers, same size.
  const auto* radtan = dynamic_cast<const PinholeRadtan*>(description.streams[2].camera_model.get());
  ASSERT_NE(radtan, nullptr);
  const PinholeRadtanIntrinsics& k = radtan->intrinsics();
  const PinholeRadtanIntrinsics& k_written =
      dynamic_cast<const PinholeRadtan&>(*written[2].camera_model).intrinsics();
  const PinholeIntrinsics &p = k.pinhole, &p_written = k_written.pinhole;
  EXPECT_EQ(std::vector<double>({p.fx, p.fy, p.cx, p.cy, k.k1, k.k2, k.p1, k.p2, k.k3}),
            std::vector<double>({p_written.fx, p_written.fy, p_written.cx, p_written.cy, k_written.k1,
                                 k_written.k2, k_written.p1, k_written.p2, k_written.k3}));
  EXPECT_EQ(radtan->width(), 640);
  const auto* fisheye = dynamic_cast<const Equidistant*>(description.streams[5].camera_model.get());
  ASSERT_NE(fisheye, nullptr);
  EXPECT_EQ(fisheye->intrinsics().k4, -1e-4);
  EXPECT_EQ(fisheye->intrinsics().pinhole.cx, 640.1);
  EXPECT_EQ(fisheye->height(), 1024);
  EXPECT_EQ(description.streams[0].camera_model, nullptr);
  ASSERT_TRUE(description.ground_truth);
  auto ground_truth = ReadTumTrajectory(description.ground_truth->string());
  ASSERT_TRUE(ground_truth.ok()) << ground_truth.error();
  EXPECT_EQ(ground_truth->stamps[1], 1'700'000'000'223'456'789);

  // Delivered merged by stamp (ties: lower stream first); each equal to what was written.
  std::vector<Measurement> expected = Measurements();
  std::stable_sort(expected.begin(), expected.end(), [](const Measurement& a, const Measurement& b) {
    return std::make_pair(StampOf(a.data), a.stream) < std::make_pair(StampOf(b.data), b.stream);
  });
  for (const Measurement& want : expected) {
    auto next = (*reader)->Next();
    ASSERT_TRUE(next.ok()) << next.error();
    ASSERT_TRUE(*next);
    EXPECT_EQ((*next)->stream, want.stream);
    ExpectEqual((*next)->data, want.data);
  }
  auto end = (*reader)->Next();
  ASSERT_TRUE(end.ok());
  EXPECT_FALSE(*end);
  EXPECT_TRUE((*reader)->warnings().empty());
}

TEST(UltrafusionDataset, AzimuthTimesAreKeptAsStoredOrDerivedAgainByAConvention) {
  TempDir dir;
  std::vector<StreamInfo> streams(1);
  streams[0].kind = SensorKind::kLidar;
  streams[0].name = "lidar";
  LidarScan scan;  // forward and left, their times stored as clockwise from behind gives them
  scan.stamp = 1'000;
  scan.end = scan.stamp + 100'000'000;
  scan.has_point_times = scan.point_times_from_azimuth = true;
  scan.points = {{10, 0, 0, 0, 0, 50'000'000}, {0, 10, 0, 0, 0, 25'000'000}};
  {
    auto writer = UltrafusionDatasetWriter::Create(dir.path(), streams);
    ASSERT_TRUE(writer.ok()) << writer.error();
    ASSERT_TRUE(writer->Write({0, scan}).ok());
    ASSERT_TRUE(writer->Finish().ok());
  }
  auto read = [&](const DatasetOptions& options) {
    auto reader = OpenUltrafusionFolder(dir.path(), options);
    EXPECT_TRUE(reader.ok()) << reader.error();
    auto next = (*reader)->Next();
    EXPECT_TRUE(next.ok() && *next);
    return std::make_pair(std::get<LidarScan>((*next)->data), (*reader)->description().streams[0]);
  };
  const auto [stored, stored_info] = read({});
  EXPECT_EQ(stored.points[1].offset_ns, 25'000'000);
  EXPECT_EQ(stored_info.point_time, PointTimeConvention::kAzimuth);
  EXPECT_FALSE(stored_info.azimuth_convention.has_value());  // not recorded in the dataset
  DatasetOptions options;
  options.point_time_convention = AzimuthConvention{AzimuthSweep::kCounterClockwise, SweepStart::kBehind};
  const auto [derived, derived_info] = read(options);
  EXPECT_EQ(derived.points[0].offset_ns, 50'000'000);
  EXPECT_EQ(derived.points[1].offset_ns, 75'000'000);  // left: three quarters counter-clockwise from behind
  EXPECT_EQ(derived_info.azimuth_convention, options.point_time_convention);
}

TEST(UltrafusionDataset, AnUnfinishedWriteLeavesNoDataset) {
  TempDir dir;
  {
    auto writer = UltrafusionDatasetWriter::Create(dir.path() / "sim", Streams());
    ASSERT_TRUE(writer.ok());
    for (const Measurement& m : Measurements()) ASSERT_TRUE(writer->Write(m).ok());
    EXPECT_FALSE(fs::exists(dir.path() / "sim" / "dataset.yaml"));
    EXPECT_FALSE(fs::exists(dir.path() / "sim" / "imu.csv"));  // still under its temporary name
  }                                                            // destroyed without Finish()
  EXPECT_FALSE(fs::exists(dir.path() / "sim" / "dataset.yaml"));
  for (const auto& entry : fs::directory_iterator(dir.path() / "sim"))
    EXPECT_TRUE(entry.is_directory()) << "left behind: " << entry.path();  // only the camera folders
  EXPECT_FALSE(OpenUltrafusionFolder(dir.path() / "sim").ok());

  WriteDataset(dir.path() / "done");
  auto again = UltrafusionDatasetWriter::Create(dir.path() / "done", Streams());
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.error().find("already holds a dataset"), std::string::npos);
}

TEST(UltrafusionDataset, WriterRejectsMisuse) {
  TempDir dir;
  auto writer = UltrafusionDatasetWriter::Create(dir.path(), Streams());
  ASSERT_TRUE(writer.ok());
  EXPECT_NE(writer->Write({0, WheelSample{}}).message().find("holds imu, not wheel"), std::string::npos);
  EXPECT_NE(writer->Write({9, ImuSample{}}).message().find("no stream 9"), std::string::npos);
  ImuSample imu;
  imu.stamp = 10;
  EXPECT_TRUE(writer->Write({0, imu}).ok());
  EXPECT_NE(writer->Write({0, imu}).message().find("stamp 10 ns is not after the previous 10 ns"),
            std::string::npos);
  EXPECT_NE(writer->Write({2, CameraFrame{}}).message().find("neither PNG/JPEG bytes nor a decoded image"),
            std::string::npos);
  std::vector<StreamInfo> same_camera(2);
  same_camera[0].kind = same_camera[1].kind = SensorKind::kCamera;
  same_camera[0].camera = same_camera[1].camera = 1;
  TempDir other;
  EXPECT_FALSE(UltrafusionDatasetWriter::Create(other.path(), same_camera).ok());
}

TEST(UltrafusionDataset, DamagedDatasetsGiveNamedErrors) {
  TempDir dir;
  const fs::path folder = dir.path() / "sim";
  WriteDataset(folder);
  const std::string yaml = testing::ReadText((folder / "dataset.yaml").string());
  auto open_error = [&](const std::string& text) {
    testing::WriteBytes(folder / "dataset.yaml", text);
    auto reader = OpenUltrafusionFolder(folder);
    return reader.ok() ? std::string("opened") : reader.error();
  };
  EXPECT_NE(open_error(yaml + "extra: 1\n").find("unknown key 'extra'"), std::string::npos);
  EXPECT_NE(
      open_error(testing::Replaced(yaml, "kind: wheel", "kind: radar")).find("streams[3]: kind 'radar'"),
      std::string::npos);
  EXPECT_NE(open_error(testing::Replaced(yaml, "file: imu.csv", "file: ../imu.csv"))
                .find("is not inside the folder"),
            std::string::npos);
  EXPECT_NE(open_error("format: ultrafusion-dataset\nversion: 2\nstreams: []\n").find("version must be 1"),
            std::string::npos);
  EXPECT_NE(open_error("[").find("dataset.yaml: "), std::string::npos);
  testing::WriteBytes(folder / "dataset.yaml", yaml);

  // A corrupt point count in lidar.bin: an error naming the byte offset, no huge allocation.
  std::string lidar = testing::ReadText((folder / "lidar.bin").string());
  const std::string original_lidar = lidar;
  lidar[24 + 7] = 0x40;  // point_count of the first record ~ 2^62
  testing::WriteBytes(folder / "lidar.bin", lidar);
  auto reader = OpenUltrafusionFolder(folder);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("lidar.bin: byte offset 24: point_count"), std::string::npos)
      << reader.error();

  // A truncated second record: the first scan (the earliest measurement) is delivered, then the error.
  testing::WriteBytes(folder / "lidar.bin", original_lidar.substr(0, original_lidar.size() - 10));
  reader = OpenUltrafusionFolder(folder);
  ASSERT_TRUE(reader.ok()) << reader.error();
  Expected<std::optional<Measurement>> next = std::optional<Measurement>();
  int delivered = 0;
  while (next.ok() && (next = (*reader)->Next()).ok() && *next) ++delivered;
  ASSERT_FALSE(next.ok());
  EXPECT_NE(next.error().find("lidar.bin: byte offset " + std::to_string(kLidarRecordHeaderBytes + 2 * 22) +
                              ": truncated record"),
            std::string::npos)
      << next.error();
  EXPECT_EQ(delivered, 1);
  testing::WriteBytes(folder / "lidar.bin", original_lidar);

  // A corrupt CSV value names the file and line.
  testing::WriteBytes(folder / "gnss.csv", "# header\n1700000000123456792,91,0,0,1,0,0,0,1,0,0,0,1,fix\n");
  EXPECT_NE(OpenUltrafusionFolder(folder).error().find("gnss.csv:2: latitude out of -90..90"),
            std::string::npos);
}

TEST(LidarRecordFile, RejectsBadMagicFlagsAndOrder) {
  TempDir dir;
  LidarScan scan;
  scan.stamp = 5;
  scan.end = 4;
  std::string record = EncodeLidarRecord(scan);
  testing::WriteBytes(dir.File("end.bin"), record);
  auto reader = LidarRecordReader::Open(dir.File("end.bin"));
  ASSERT_TRUE(reader.ok());
  EXPECT_NE(reader->Next().error().find("byte offset 16: end_ns 4 is before stamp_ns 5"), std::string::npos);
  scan.end = 5;
  record = EncodeLidarRecord(scan);
  record[4] = 8;
  testing::WriteBytes(dir.File("flags.bin"), record);
  EXPECT_NE(LidarRecordReader::Open(dir.File("flags.bin"))->Next().error().find("unknown flags 8"),
            std::string::npos);
  record[0] = 'X';
  testing::WriteBytes(dir.File("magic.bin"), record);
  EXPECT_NE(LidarRecordReader::Open(dir.File("magic.bin"))->Next().error().find("magic"), std::string::npos);
}

}  // namespace
}  // namespace uf
