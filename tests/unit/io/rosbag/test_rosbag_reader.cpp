// The ROS bag reader end to end, on bags written by librosbag at test time: every message type under every
// chunk compression, stamps, IMU units, topic selection and messages damaged one at a time.
#include <gtest/gtest.h>

#include <map>

#include "odometry/io/rosbag/imu_unit.h"
#include "odometry/io/rosbag/rosbag_reader.h"
#include "tests/unit/io/rosbag/bag_test_util.h"

namespace uf {
namespace {

using testing::BagCompression;
using testing::BagEntry;
using testing::ReadAll;
using testing::TempDir;
using testing::Vec3;

constexpr Stamp kT0 = 1'600'000'000'000'000'000;
constexpr Stamp kMs = 1'000'000;

// Header stamp `stamp`, recorded 1 ms later.
BagEntry Entry(const std::string& topic, Stamp stamp, testing::RosMessage message) {
  return BagEntry{topic, stamp + kMs, std::move(message)};
}

std::vector<BagEntry> EveryTypeBag() {
  std::vector<BagEntry> entries;
  const std::array<double, 9> diagonal = {4, 0, 0, 0, 9, 0, 0, 0, 16};
  for (int i = 0; i < 20; ++i) {
    const Stamp t = kT0 + i * 10 * kMs;
    entries.push_back(Entry(
        "/imu", t, testing::MakeImu(t, "imu_link", {0.1, 0.2, 9.8 + 0.001 * i}, {0.01, 0.02, i * 0.1})));
    if (i % 5 == 0) entries.push_back(Entry("/velodyne_points", t, testing::VelodyneCloud(t, 4)));
    if (i % 8 == 1) {
      entries.push_back(Entry("/livox/lidar", t,
                              testing::MakeLivoxCustomMsg(t, "livox", static_cast<std::uint64_t>(t),
                                                          {{0, 1, 2, 3, 4, 0, 1}, {500, 5, 6, 7, 8, 0, 2}})));
    }
    if (i % 7 == 2) {
      entries.push_back(Entry("/camera/image_raw", t,
                              testing::MakeImage(t, "cam0", 4, 2, "mono8", 4, {1, 2, 3, 4, 5, 6, 7, 8})));
      entries.push_back(
          Entry("/camera1/compressed", t,
                testing::MakeCompressedImage(t, "cam1", "rgb8; jpeg compressed bgr8", {0xff, 0xd8, 0xff})));
    }
    if (i % 9 == 3) {
      entries.push_back(Entry(
          "/fix", t,
          testing::MakeNavSatFix(t, "gps", i == 3 ? 2 : -1, 42.1, -71.2, 10.5, diagonal, i == 3 ? 2 : 0)));
    }
    if (i % 6 == 4) {
      entries.push_back(
          Entry("/odom", t, testing::MakeOdometry(t, "odom", "base_link", {1.5, 0, 0}, {0, 0, 0.25})));
      entries.push_back(
          Entry("/twist", t, testing::MakeTwistStamped(t, "base_footprint", {0.5, 0, 0}, {0, 0, -0.5})));
      entries.push_back(
          Entry("/chatter", t, testing::MakeRaw("std_msgs/String", {3, 0, 0, 0, 'a', 'b', 'c'})));
    }
  }
  return entries;
}

class RosBagEveryCompression : public ::testing::TestWithParam<BagCompression> {};

TEST_P(RosBagEveryCompression, EveryMessageTypeInRecordOrder) {
  TempDir dir;
  const std::string path = dir.File("every_type.bag");
  const std::vector<BagEntry> entries = EveryTypeBag();
  ASSERT_EQ(testing::WriteBag(path, entries, GetParam(), 2048), "");  // small chunks: many of them

  auto reader = OpenRosBag(path, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  const DatasetDescription& description = (*reader)->description();
  EXPECT_EQ(description.format, DatasetFormat::kRosBag);
  std::map<std::string, const StreamInfo*> by_name;
  for (const StreamInfo& info : description.streams) by_name[info.name] = &info;
  ASSERT_EQ(by_name.size(), 8u);  // /chatter (std_msgs/String) is ignored
  EXPECT_EQ(by_name["/imu"]->kind, SensorKind::kImu);
  EXPECT_EQ(by_name["/imu"]->imu_accel_unit, "m/s^2");  // detected at open
  EXPECT_EQ(by_name["/velodyne_points"]->kind, SensorKind::kLidar);
  EXPECT_EQ(by_name["/livox/lidar"]->message_type, "livox_ros_driver/CustomMsg");
  EXPECT_EQ(by_name["/camera/image_raw"]->camera, 0);  // numbered in order of appearance
  EXPECT_EQ(by_name["/camera1/compressed"]->camera, 1);
  EXPECT_EQ(by_name["/fix"]->kind, SensorKind::kGnss);
  EXPECT_EQ(by_name["/odom"]->kind, SensorKind::kWheel);
  EXPECT_EQ(by_name["/twist"]->kind, SensorKind::kWheel);

  const std::vector<Measurement> all = ReadAll(**reader);
  // Record order: the written sequence without /chatter.
  std::vector<const BagEntry*> expected;
  for (const BagEntry& entry : entries) {
    if (entry.topic != "/chatter") expected.push_back(&entry);
  }
  ASSERT_EQ(all.size(), expected.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(description.streams[all[i].stream].name, expected[i]->topic) << i;
    EXPECT_EQ(StampOf(all[i].data), expected[i]->record_time_ns - kMs) << i;  // the header stamp
  }
  EXPECT_TRUE((*reader)->warnings().empty());
  EXPECT_EQ(by_name["/imu"]->frame_id, "imu_link");
  EXPECT_EQ(by_name["/odom"]->frame_id, "base_link");  // the twist's frame: child_frame_id
  EXPECT_EQ(by_name["/velodyne_points"]->point_time, PointTimeConvention::kRelativeSeconds);
  EXPECT_EQ(by_name["/velodyne_points"]->point_time_field, "time");
  EXPECT_EQ(by_name["/livox/lidar"]->point_time, PointTimeConvention::kLivoxOffsetNanoseconds);

  for (const Measurement& m : all) {
    const std::string& topic = description.streams[m.stream].name;
    if (topic == "/imu") {
      const auto& imu = std::get<ImuSample>(m.data);
      const int i = static_cast<int>((imu.stamp - kT0) / (10 * kMs));
      EXPECT_DOUBLE_EQ(imu.acc.z(), 9.8 + 0.001 * i);
      EXPECT_DOUBLE_EQ(imu.acc.x(), 0.1);
      EXPECT_DOUBLE_EQ(imu.gyro.z(), i * 0.1);
    } else if (topic == "/velodyne_points") {
      const auto& scan = std::get<LidarScan>(m.data);
      ASSERT_EQ(scan.points.size(), 4u);
      EXPECT_EQ(scan.points[3].offset_ns, std::llround(static_cast<double>(3 * 1e-4f) * 1e9));
      EXPECT_EQ(scan.points[3].ring, 3);
    } else if (topic == "/livox/lidar") {
      const auto& scan = std::get<LidarScan>(m.data);
      ASSERT_EQ(scan.points.size(), 2u);
      EXPECT_EQ(scan.points[1].offset_ns, 500);
      EXPECT_EQ(scan.points[1].ring, 2);
    } else if (topic == "/camera/image_raw") {
      const auto& frame = std::get<CameraFrame>(m.data);
      EXPECT_EQ(frame.camera, 0);
      EXPECT_EQ(frame.encoded.format, "mono8");
      EXPECT_EQ(frame.encoded.width, 4);
      EXPECT_EQ(frame.encoded.height, 2);
      EXPECT_EQ(frame.encoded.row_step, 4);
      EXPECT_EQ(frame.encoded.bytes, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));
      EXPECT_TRUE(frame.image.empty());
    } else if (topic == "/camera1/compressed") {
      const auto& frame = std::get<CameraFrame>(m.data);
      EXPECT_EQ(frame.camera, 1);
      EXPECT_EQ(frame.encoded.format, "jpeg");
      EXPECT_EQ(frame.encoded.bytes.size(), 3u);
    } else if (topic == "/fix") {
      const auto& fix = std::get<GnssFix>(m.data);
      EXPECT_DOUBLE_EQ(fix.latitude_deg, 42.1);
      EXPECT_DOUBLE_EQ(fix.longitude_deg, -71.2);
      EXPECT_DOUBLE_EQ(fix.altitude_m, 10.5);
      if (fix.stamp == kT0 + 30 * kMs) {
        EXPECT_EQ(fix.status, GnssFixStatus::kRtkFloat);  // GBAS
        EXPECT_DOUBLE_EQ(fix.covariance_enu(1, 1), 9);
        EXPECT_DOUBLE_EQ(fix.covariance_enu(2, 2), 16);
      } else {
        EXPECT_EQ(fix.status, GnssFixStatus::kNoFix);
        EXPECT_TRUE(fix.covariance_enu.isIdentity());  // covariance type unknown
      }
    } else if (topic == "/odom") {
      const auto& wheel = std::get<WheelSample>(m.data);
      EXPECT_DOUBLE_EQ(wheel.linear_velocity.x(), 1.5);
      EXPECT_DOUBLE_EQ(wheel.angular_velocity.z(), 0.25);
    } else if (topic == "/twist") {
      const auto& wheel = std::get<WheelSample>(m.data);
      EXPECT_DOUBLE_EQ(wheel.linear_velocity.x(), 0.5);
      EXPECT_DOUBLE_EQ(wheel.angular_velocity.z(), -0.5);
    }
  }
  // The end stays the end.
  auto after = (*reader)->Next();
  ASSERT_TRUE(after.ok());
  EXPECT_FALSE(after->has_value());
}

INSTANTIATE_TEST_SUITE_P(Compressions, RosBagEveryCompression,
                         ::testing::Values(BagCompression::kNone, BagCompression::kBz2,
                                           BagCompression::kLz4));

TEST(RosBagReader, BackwardsAndZeroStampsAreDeliveredAsRecorded) {
  TempDir dir;
  const std::string path = dir.File("stamps.bag");
  std::vector<BagEntry> entries;
  const Stamp header_stamps[] = {kT0 + 50 * kMs, kT0 + 40 * kMs, 0, kT0 + 60 * kMs};
  for (int i = 0; i < 4; ++i) {
    entries.push_back(
        {"/odom", kT0 + i * kMs, testing::MakeOdometry(header_stamps[i], "odom", "base", {}, {})});
  }
  ASSERT_EQ(testing::WriteBag(path, entries), "");
  auto reader = OpenRosBag(path, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  const std::vector<Measurement> all = ReadAll(**reader);
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(StampOf(all[0].data), kT0 + 50 * kMs);
  EXPECT_EQ(StampOf(all[1].data), kT0 + 40 * kMs);  // backwards: not reordered here
  EXPECT_EQ(StampOf(all[2].data), kT0 + 2 * kMs);   // zero header stamp: the record time
  EXPECT_EQ(StampOf(all[3].data), kT0 + 60 * kMs);
  ASSERT_EQ((*reader)->warnings().size(), 1u);
  EXPECT_EQ((*reader)->warnings()[0].stream, "/odom");
  EXPECT_NE((*reader)->warnings()[0].what.find("header stamp is zero"), std::string::npos);
  EXPECT_EQ((*reader)->warnings()[0].count, 1);
}

std::vector<BagEntry> ImuBag(double acc_z, int samples, const std::string& topic = "/imu") {
  std::vector<BagEntry> entries;
  for (int i = 0; i < samples; ++i) {
    const Stamp t = kT0 + i * 10 * kMs;
    entries.push_back(Entry(topic, t, testing::MakeImu(t, "imu", {0.01, -0.02, acc_z}, {0, 0, 0.5})));
  }
  return entries;
}

TEST(RosBagReader, ImuInGIsDetectedAndConverted) {
  TempDir dir;
  const std::string path = dir.File("g.bag");
  ASSERT_EQ(testing::WriteBag(path, ImuBag(1.0, 150), BagCompression::kLz4), "");
  auto reader = OpenRosBag(path, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ((*reader)->description().streams.at(0).imu_accel_unit, "g");
  const std::vector<Measurement> all = ReadAll(**reader);
  ASSERT_EQ(all.size(), 150u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto& imu = std::get<ImuSample>(all[i].data);
    EXPECT_EQ(imu.stamp, kT0 + static_cast<Stamp>(i) * 10 * kMs);
    EXPECT_DOUBLE_EQ(imu.acc.z(), kStandardGravity);
    EXPECT_DOUBLE_EQ(imu.gyro.z(), 0.5);
  }
}

TEST(RosBagReader, ImuUnitFromOptionsOrAnErrorNamingTopicAndValue) {
  TempDir dir;
  const std::string path = dir.File("odd.bag");
  ASSERT_EQ(testing::WriteBag(path, ImuBag(3.0, 150, "/imu/odd")), "");
  auto reader = OpenRosBag(path, {});
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("/imu/odd"), std::string::npos) << reader.error();
  EXPECT_NE(reader.error().find("3"), std::string::npos) << reader.error();

  DatasetOptions options;
  options.imu_accel_unit = ImuAccelUnit::kStandardGravity;
  reader = OpenRosBag(path, options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ((*reader)->description().streams.at(0).imu_accel_unit, "g");
  const std::vector<Measurement> all = ReadAll(**reader);
  ASSERT_EQ(all.size(), 150u);
  EXPECT_DOUBLE_EQ(std::get<ImuSample>(all[0].data).acc.z(), 3.0 * kStandardGravity);
}

TEST(RosBagReader, SelectedTopicsAreReadExactly) {
  TempDir dir;
  const std::string path = dir.File("every_type.bag");
  ASSERT_EQ(testing::WriteBag(path, EveryTypeBag()), "");
  DatasetOptions options;
  const SE3 T_body_wheel(SO3::Exp(Eigen::Vector3d(0, 0, 0.5)), Eigen::Vector3d(-0.3, 0, -0.2));
  options.topics = {{"/twist", SensorKind::kWheel, T_body_wheel}, {"/imu", SensorKind::kImu, std::nullopt}};
  auto reader = OpenRosBag(path, options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_EQ((*reader)->description().streams.size(), 2u);
  EXPECT_EQ((*reader)->description().streams[0].name, "/twist");
  EXPECT_EQ((*reader)->description().streams[1].name, "/imu");
  // The extrinsic given with a topic is the stream's; a topic without one has none.
  ASSERT_TRUE((*reader)->description().streams[0].T_body_sensor.has_value());
  EXPECT_TRUE((*reader)->description().streams[0].T_body_sensor->matrix().isApprox(T_body_wheel.matrix()));
  EXPECT_FALSE((*reader)->description().streams[1].T_body_sensor.has_value());
  const std::vector<Measurement> all = ReadAll(**reader);
  std::map<int, int> counts;
  for (const Measurement& m : all) ++counts[m.stream];
  EXPECT_EQ(counts[0], 3);
  EXPECT_EQ(counts[1], 20);

  options.topics = {{"/imu_missing", SensorKind::kImu, std::nullopt}};
  reader = OpenRosBag(path, options);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("/imu_missing"), std::string::npos) << reader.error();
  options.topics = {{"/odom", SensorKind::kLidar, std::nullopt}};
  reader = OpenRosBag(path, options);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("/odom"), std::string::npos) << reader.error();
  EXPECT_NE(reader.error().find("nav_msgs/Odometry"), std::string::npos) << reader.error();
  options.topics = {{"/chatter", SensorKind::kWheel, std::nullopt}};
  EXPECT_FALSE(OpenRosBag(path, options).ok());
}

TEST(RosBagReader, EmptyBagAndLivoxDriver2) {
  TempDir dir;
  const std::string empty = dir.File("empty.bag");
  ASSERT_EQ(testing::WriteBag(empty, {}), "");
  auto reader = OpenRosBag(empty, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_TRUE((*reader)->description().streams.empty());
  EXPECT_TRUE(ReadAll(**reader).empty());

  const std::string livox = dir.File("livox2.bag");
  ASSERT_EQ(
      testing::WriteBag(livox, {Entry("/livox", kT0,
                                      testing::MakeLivoxCustomMsg(kT0, "l", kT0, {{7, 1, 1, 1, 0, 0, 0}},
                                                                  "livox_ros_driver2/CustomMsg"))}),
      "");
  reader = OpenRosBag(livox, {});
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_EQ((*reader)->description().streams.size(), 1u);
  EXPECT_EQ((*reader)->description().streams[0].kind, SensorKind::kLidar);
  const std::vector<Measurement> all = ReadAll(**reader);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(std::get<LidarScan>(all[0].data).stamp, kT0);
}

}  // namespace
}  // namespace uf
