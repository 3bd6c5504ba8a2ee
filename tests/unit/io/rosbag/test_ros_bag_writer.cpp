// The bag writer end to end: measurements of every kind written with RosBagWriter (librosbag underneath)
// come back from the project's own reader, and from librosbag, unchanged.
#include <gtest/gtest.h>

#include "odometry/io/image_decode.h"
#include "odometry/io/rosbag/ros_bag_writer.h"
#include "odometry/io/rosbag/rosbag_reader.h"
#include "tests/unit/io/rosbag/bag_test_util.h"

namespace uf {
namespace {

constexpr Stamp kT0 = 1'700'000'000'123'456'789;
constexpr Stamp kMs = 1'000'000;

std::vector<BagTopic> Topics() {
  return {{"/imu", "imu_link", SensorKind::kImu},
          {"/points", "lidar", SensorKind::kLidar},
          {"/cam0/compressed", "cam0", SensorKind::kCamera},
          {"/wheel_odom", "base_link", SensorKind::kWheel},
          {"/fix", "gnss", SensorKind::kGnss}};
}

ImuSample Imu(Stamp t, const Eigen::Vector3d& acc, const Eigen::Vector3d& gyro) {
  ImuSample sample;
  sample.stamp = t;
  sample.acc = acc;
  sample.gyro = gyro;
  return sample;
}

WheelSample Wheel(Stamp t, double v, double w) {
  WheelSample sample;
  sample.stamp = t;
  sample.linear_velocity = {v, 0, 0};
  sample.angular_velocity = {0, 0, w};
  return sample;
}

GnssFix Fix(Stamp t, double latitude) {
  GnssFix fix;
  fix.stamp = t;
  fix.latitude_deg = latitude;
  fix.longitude_deg = 8.4;
  fix.altitude_m = 115.25;
  fix.covariance_enu = Eigen::Matrix3d::Identity() * 0.04;
  fix.covariance_enu(0, 1) = fix.covariance_enu(1, 0) = 0.01;
  fix.status = GnssFixStatus::kSbas;
  return fix;
}

LidarScan Scan(Stamp t) {
  LidarScan scan;
  scan.stamp = t;
  scan.end = t + 100 * kMs;
  scan.has_point_times = scan.has_ring = true;
  for (int i = 0; i < 50; ++i)
    scan.points.push_back({1.5f * i, -2.0f, 0.25f, float(i % 7), std::uint16_t(i % 32), i * 1'999'999});
  return scan;
}

CameraFrame Frame(Stamp t) {
  CameraFrame frame;
  frame.stamp = t;
  frame.image = Image{4, 3, 3, {}};
  for (int i = 0; i < 36; ++i) frame.image.pixels.push_back(static_cast<std::uint8_t>(7 * i));
  return frame;
}

// Out of line: gcc 12 at -O3 warns falsely (maybe-uninitialized) about the variant when this is inlined.
[[gnu::noinline]] void Add(std::vector<Measurement>& all, int stream, MeasurementData data) {
  all.push_back(Measurement{stream, std::move(data)});
}

// Time-ordered: imu every 10 ms, lidar and camera every 100 ms, wheel every 20 ms, gnss every 200 ms.
std::vector<Measurement> Measurements() {
  std::vector<Measurement> all;
  for (int i = 0; i < 40; ++i) {
    const Stamp t = kT0 + i * 10 * kMs;
    Add(all, 0, Imu(t, {0.1 * i, -0.2, 9.81}, {0.01, 0.02 * i, -0.03}));
    if (i % 10 == 0) Add(all, 1, Scan(t));
    if (i % 10 == 5) Add(all, 2, Frame(t));
    if (i % 2 == 0) Add(all, 3, Wheel(t, 1.5 + i, -0.1 * i));
    if (i % 20 == 3) Add(all, 4, Fix(t, 49.0 + 1e-7 * i));
  }
  return all;
}

TEST(RosBagWriter, EveryKindReadsBackThroughTheProjectReader) {
  testing::TempDir dir;
  const std::string path = dir.File("sim.bag");
  auto writer = RosBagWriter::Create(path, Topics());
  ASSERT_TRUE(writer.ok()) << writer.error();
  const std::vector<Measurement> written = Measurements();
  for (const Measurement& m : written) ASSERT_TRUE(writer->Write(m.stream, m.data).ok());
  EXPECT_FALSE(std::filesystem::exists(path)) << "the bag appears only after Finish()";
  ASSERT_TRUE(writer->Finish().ok());

  auto reader = OpenRosBag(path, DatasetOptions{});
  ASSERT_TRUE(reader.ok()) << reader.error();
  const auto& streams = (*reader)->description().streams;
  ASSERT_EQ(streams.size(), 5u);
  std::map<std::string, int> stream_of_topic;
  for (std::size_t i = 0; i < streams.size(); ++i) stream_of_topic[streams[i].name] = static_cast<int>(i);
  const std::vector<Measurement> read = testing::ReadAll(**reader);
  ASSERT_EQ(read.size(), written.size());

  // The reader returns storage order, which is the write order here.
  for (std::size_t i = 0; i < read.size(); ++i) {
    const Measurement& w = written[i];
    const Measurement& r = read[i];
    ASSERT_EQ(r.stream, stream_of_topic.at(Topics()[w.stream].topic)) << i;
    ASSERT_EQ(StampOf(r.data), StampOf(w.data)) << i;
    if (const auto* imu = std::get_if<ImuSample>(&w.data)) {
      EXPECT_EQ(std::get<ImuSample>(r.data).acc, imu->acc);
      EXPECT_EQ(std::get<ImuSample>(r.data).gyro, imu->gyro);
    } else if (const auto* scan = std::get_if<LidarScan>(&w.data)) {
      const auto& back = std::get<LidarScan>(r.data);
      ASSERT_EQ(back.points.size(), scan->points.size());
      EXPECT_TRUE(back.has_point_times && back.has_ring && !back.point_times_from_azimuth);
      for (std::size_t p = 0; p < back.points.size(); ++p) {
        EXPECT_EQ(back.points[p].x, scan->points[p].x);
        EXPECT_EQ(back.points[p].intensity, scan->points[p].intensity);
        EXPECT_EQ(back.points[p].ring, scan->points[p].ring);
        EXPECT_EQ(back.points[p].offset_ns, scan->points[p].offset_ns);  // uint32 ns: exact
      }
    } else if (const auto* frame = std::get_if<CameraFrame>(&w.data)) {
      CameraFrame back = std::get<CameraFrame>(r.data);
      ASSERT_TRUE(DecodeCameraFrame(back).ok());
      EXPECT_EQ(back.image.pixels, frame->image.pixels);  // PNG is lossless
      EXPECT_EQ(back.image.channels, 3);
    } else if (const auto* wheel = std::get_if<WheelSample>(&w.data)) {
      EXPECT_EQ(std::get<WheelSample>(r.data).linear_velocity, wheel->linear_velocity);
      EXPECT_EQ(std::get<WheelSample>(r.data).angular_velocity, wheel->angular_velocity);
    } else if (const auto* fix = std::get_if<GnssFix>(&w.data)) {
      const auto& back = std::get<GnssFix>(r.data);
      EXPECT_EQ(back.latitude_deg, fix->latitude_deg);
      EXPECT_EQ(back.altitude_m, fix->altitude_m);
      EXPECT_EQ(back.covariance_enu, fix->covariance_enu);
      EXPECT_EQ(back.status, GnssFixStatus::kSbas);
    }
  }
}

TEST(RosBagWriter, LibrosbagReadsIt) {
  testing::TempDir dir;
  const std::string path = dir.File("sim.bag");
  auto writer = RosBagWriter::Create(path, Topics());
  ASSERT_TRUE(writer.ok());
  const std::vector<Measurement> written = Measurements();
  for (const Measurement& m : written) ASSERT_TRUE(writer->Write(m.stream, m.data).ok());
  ASSERT_TRUE(writer->Finish().ok());
  std::string error;
  const auto messages = testing::ReadBagWithLibrosbag(path, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_EQ(messages.size(), written.size());
  std::map<std::string, int> types;
  for (const auto& message : messages) ++types[message.type];
  const std::map<std::string, int> expected = {{"sensor_msgs/Imu", 40},
                                               {"sensor_msgs/PointCloud2", 4},
                                               {"sensor_msgs/CompressedImage", 4},
                                               {"nav_msgs/Odometry", 20},
                                               {"sensor_msgs/NavSatFix", 2}};
  EXPECT_EQ(types, expected);
  EXPECT_EQ(messages.front().record_time_ns, kT0);  // record time = header stamp
}

TEST(RosBagWriter, MisuseAndAbandonedWritesLeaveNoBag) {
  testing::TempDir dir;
  const std::string path = dir.File("sim.bag");
  {
    auto writer = RosBagWriter::Create(path, Topics());
    ASSERT_TRUE(writer.ok());
    EXPECT_NE(writer->Write(0, Wheel(kT0, 1, 0)).message().find("does not match topic 0"), std::string::npos);
    EXPECT_NE(writer->Write(7, Imu(kT0, {0, 0, 9.8}, {0, 0, 0})).message().find("topic 7"),
              std::string::npos);
    EXPECT_NE(writer->Write(0, Imu(-5, {0, 0, 9.8}, {0, 0, 0})).message().find("before 1970"),
              std::string::npos);
  }  // no Finish()
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_FALSE(RosBagWriter::Create(dir.File("missing/folder/x.bag"), Topics()).ok());
}

}  // namespace
}  // namespace uf
