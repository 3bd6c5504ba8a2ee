// livox_ros_driver CustomMsg from its serialized bytes: timebase + offset_time per point.
#include <gtest/gtest.h>

#include <limits>

#include "odometry/io/rosbag/livox_custom_decode.h"
#include "tests/unit/io/rosbag/ros_bag_fixtures.h"

namespace uf {
namespace {

using testing::LivoxPoint;
using testing::MakeLivoxCustomMsg;

constexpr Stamp kTimebase = 1'650'000'000'000'000'123;

TEST(LivoxCustomDecode, PointTimesAreTimebasePlusOffset) {
  const std::vector<LivoxPoint> points = {
      {0, 1, 2, 3, 10, 0, 0}, {50'000, 4, 5, 6, 20, 0x10, 3}, {99'999'000, 7, 8, 9, 30, 0, 5}};
  const auto message = MakeLivoxCustomMsg(kTimebase, "livox_frame", kTimebase, points);
  std::string frame;
  bool stamp_zero = true;
  const auto decoded = DecodeLivoxCustomMsg(message.bytes, 0, 0.1, &frame, &stamp_zero);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(frame, "livox_frame");
  EXPECT_FALSE(stamp_zero);
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kLivoxOffsetNanoseconds);
  EXPECT_EQ(decoded->point_time_field, "offset_time");
  const LidarScan& scan = decoded->scan;
  EXPECT_EQ(scan.stamp, kTimebase);
  EXPECT_EQ(scan.end, kTimebase + 99'999'000);
  ASSERT_EQ(scan.points.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(scan.points[i].offset_ns, static_cast<std::int32_t>(points[i].offset_time));
    EXPECT_EQ(scan.points[i].x, points[i].x);
    EXPECT_EQ(scan.points[i].intensity, points[i].reflectivity);
    EXPECT_EQ(scan.points[i].ring, points[i].line);
  }
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_TRUE(scan.has_ring);
}

TEST(LivoxCustomDecode, HeaderStampedAfterTheTimebaseAndZeroHeaderStamp) {
  const std::vector<LivoxPoint> points = {{1000, 1, 0, 0, 0, 0, 0}, {2000, 0, 1, 0, 0, 0, 0}};
  auto message = MakeLivoxCustomMsg(kTimebase + 100'000'000, "f", kTimebase, points);
  auto decoded = DecodeLivoxCustomMsg(message.bytes, 0, 0.1);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->scan.stamp, kTimebase + 1000);  // the earliest point, before the header
  EXPECT_EQ(decoded->scan.points[0].offset_ns, 0);
  EXPECT_EQ(decoded->scan.points[1].offset_ns, 1000);

  message = MakeLivoxCustomMsg(0, "f", kTimebase, points);
  bool stamp_zero = false;
  decoded = DecodeLivoxCustomMsg(message.bytes, kTimebase - 5, 0.1, nullptr, &stamp_zero);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_TRUE(stamp_zero);
  EXPECT_EQ(decoded->scan.stamp, kTimebase - 5);  // the fallback (record time) precedes every point
  EXPECT_EQ(decoded->scan.points[0].offset_ns, 1005);
}

TEST(LivoxCustomDecode, NonFinitePointsDroppedAndShortMessagesRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<LivoxPoint> points = {{0, nan, 0, 0, 0, 0, 0}, {10, 1, 1, 1, 0, 0, 0}};
  const auto message = MakeLivoxCustomMsg(kTimebase, "f", kTimebase, points);
  const auto decoded = DecodeLivoxCustomMsg(message.bytes, 0, 0.1);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->non_finite_points, 1);
  EXPECT_EQ(decoded->scan.points.size(), 1u);

  for (std::size_t cut = 0; cut < message.bytes.size(); ++cut) {
    const std::span<const std::uint8_t> truncated(message.bytes.data(), cut);
    const auto refused = DecodeLivoxCustomMsg(truncated, 0, 0.1);
    ASSERT_FALSE(refused.ok()) << cut;
    EXPECT_NE(refused.error().find("CustomMsg"), std::string::npos);
  }
}

}  // namespace
}  // namespace uf
