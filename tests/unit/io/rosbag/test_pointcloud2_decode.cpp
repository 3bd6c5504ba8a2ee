// The PointCloud2 decoder alone: every point time convention against the values written, the azimuth
// fallback, byte order, strides, and the layouts that must be refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "odometry/io/rosbag/pointcloud2_decode.h"

namespace uf {
namespace {

constexpr Stamp kHeader = 1'700'000'000'123'456'789;

// Velodyne layout: x y z intensity (float32), ring (uint16), time (float32, s after the header): 22 bytes.
PointCloud2Layout VelodyneLayout(std::uint32_t width) {
  PointCloud2Layout layout;
  layout.height = 1;
  layout.width = width;
  layout.point_step = 22;
  layout.row_step = 22 * width;
  layout.fields = {{"x", 0, 7, 1},          {"y", 4, 7, 1},     {"z", 8, 7, 1},
                   {"intensity", 12, 7, 1}, {"ring", 16, 4, 1}, {"time", 18, 7, 1}};
  return layout;
}

template <typename T>
void Put(std::vector<std::uint8_t>& data, std::size_t offset, T value) {
  if (data.size() < offset + sizeof(T)) data.resize(offset + sizeof(T));
  std::memcpy(data.data() + offset, &value, sizeof(T));
}

struct TestPoint {
  float x, y, z, intensity;
  std::uint16_t ring;
  float time;
};

std::vector<std::uint8_t> VelodyneData(const std::vector<TestPoint>& points) {
  std::vector<std::uint8_t> data(points.size() * 22);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t at = i * 22;
    Put(data, at, points[i].x);
    Put(data, at + 4, points[i].y);
    Put(data, at + 8, points[i].z);
    Put(data, at + 12, points[i].intensity);
    Put(data, at + 16, points[i].ring);
    Put(data, at + 18, points[i].time);
  }
  return data;
}

LidarDecodeOptions NoAzimuth() {
  LidarDecodeOptions options;
  options.derive_point_times_from_azimuth = false;
  return options;
}

TEST(PointCloud2Decode, VelodyneRelativeSecondsGiveOffsetsFromTheHeaderStamp) {
  const std::vector<TestPoint> points = {{1, 2, 3, 10, 0, 0.0f},
                                         {4, 5, 6, 20, 15, 0.025f},
                                         {7, 8, 9, 30, 31, 0.05f},
                                         {-1, -2, -3, 40, 7, 0.0999f}};
  const auto decoded = DecodePointCloud2(kHeader, VelodyneLayout(4), VelodyneData(points), NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const LidarScan& scan = decoded->scan;
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kRelativeSeconds);
  EXPECT_EQ(decoded->point_time_field, "time");
  ASSERT_EQ(scan.points.size(), 4u);
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_FALSE(scan.point_times_from_azimuth);
  EXPECT_TRUE(scan.has_ring);
  EXPECT_EQ(scan.stamp, kHeader);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(scan.points[i].offset_ns, std::llround(static_cast<double>(points[i].time) * 1e9)) << i;
    EXPECT_EQ(scan.points[i].x, points[i].x);
    EXPECT_EQ(scan.points[i].z, points[i].z);
    EXPECT_EQ(scan.points[i].intensity, points[i].intensity);
    EXPECT_EQ(scan.points[i].ring, points[i].ring);
  }
  EXPECT_EQ(scan.end, kHeader + std::llround(static_cast<double>(0.0999f) * 1e9));
}

TEST(PointCloud2Decode, HeaderStampAtTheScanEndMovesTheStampToTheEarliestPoint) {
  const std::vector<TestPoint> points = {
      {1, 0, 0, 0, 0, -0.1f}, {0, 1, 0, 0, 0, -0.05f}, {0, 0, 1, 0, 0, 0.0f}};
  const auto decoded = DecodePointCloud2(kHeader, VelodyneLayout(3), VelodyneData(points), NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const LidarScan& scan = decoded->scan;
  const std::int64_t first = std::llround(static_cast<double>(-0.1f) * 1e9);
  EXPECT_EQ(scan.stamp, kHeader + first);
  EXPECT_EQ(scan.end, kHeader);
  EXPECT_EQ(scan.points[0].offset_ns, 0);
  EXPECT_EQ(scan.points[1].offset_ns, std::llround(static_cast<double>(-0.05f) * 1e9) - first);
  EXPECT_EQ(scan.points[2].offset_ns, -first);
}

TEST(PointCloud2Decode, OusterRelativeNanoseconds) {
  PointCloud2Layout layout;
  layout.height = 2;  // organised: rows of the image
  layout.width = 2;
  layout.point_step = 16;
  layout.row_step = 32;
  layout.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"t", 12, 6, 1}};
  std::vector<std::uint8_t> data(64);
  const std::uint32_t times[] = {0, 48'828, 97'656, 99'999'999};
  for (int i = 0; i < 4; ++i) {
    Put(data, i * 16, 1.0f + i);
    Put(data, i * 16 + 12, times[i]);
  }
  const auto decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kRelativeNanoseconds);
  EXPECT_EQ(decoded->point_time_field, "t");
  ASSERT_EQ(decoded->scan.points.size(), 4u);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(decoded->scan.points[i].offset_ns, static_cast<std::int32_t>(times[i]));
  EXPECT_EQ(decoded->scan.stamp, kHeader);
  EXPECT_EQ(decoded->scan.end, kHeader + 99'999'999);
}

PointCloud2Layout TimestampLayout() {
  PointCloud2Layout layout;
  layout.height = 1;
  layout.width = 3;
  layout.point_step = 24;
  layout.row_step = 72;
  layout.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"timestamp", 16, 8, 1}};
  return layout;
}

TEST(PointCloud2Decode, HesaiAbsoluteSeconds) {
  // Header stamped at the scan start; absolute point times in float64 seconds (~0.24 us resolution).
  const Stamp header = 1'700'000'000'000'000'000;
  const double times[] = {1700000000.0, 1700000000.05, 1700000000.099};
  std::vector<std::uint8_t> data(72);
  for (int i = 0; i < 3; ++i) {
    Put(data, i * 24, 1.0f);
    Put(data, i * 24 + 16, times[i]);
  }
  const auto decoded = DecodePointCloud2(header, TimestampLayout(), data, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kAbsoluteSeconds);
  EXPECT_EQ(decoded->scan.stamp, header);
  for (int i = 0; i < 3; ++i) {
    const double expected = (times[i] - 1700000000.0) * 1e9;  // exact in double for these values
    EXPECT_NEAR(decoded->scan.points[i].offset_ns, expected, 1.0) << i;
  }
}

TEST(PointCloud2Decode, LivoxDriver2AbsoluteNanoseconds) {
  // Multiples of 256 ns are exact in float64 at 1.7e18.
  const Stamp header = 1'700'000'000'000'000'000;
  const double times[] = {1.7e18 - 256.0 * 10, 1.7e18 + 256.0 * 1000, 1.7e18 + 256.0 * 390000};
  std::vector<std::uint8_t> data(72);
  for (int i = 0; i < 3; ++i) {
    Put(data, i * 24, 2.0f);
    Put(data, i * 24 + 16, times[i]);
  }
  const auto decoded = DecodePointCloud2(header, TimestampLayout(), data, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kAbsoluteNanoseconds);
  EXPECT_EQ(decoded->scan.stamp, header - 2560);  // the first point precedes the header
  EXPECT_EQ(decoded->scan.points[0].offset_ns, 0);
  EXPECT_EQ(decoded->scan.points[1].offset_ns, 2560 + 256000);
  EXPECT_EQ(decoded->scan.points[2].offset_ns, 2560 + 256 * 390000);
  EXPECT_EQ(decoded->scan.end, header + 256 * 390000);
}

TEST(PointCloud2Decode, WithoutTimeFieldDerivesOffsetsFromAzimuthClockwise) {
  PointCloud2Layout layout = VelodyneLayout(4);
  layout.fields.pop_back();  // no time field
  // Azimuths 0, -90, 180, +90 degrees: a clockwise sweep (seen from above) meets them in this order.
  const std::vector<TestPoint> points = {
      {1, 0, 0, 0, 0, 0}, {0, -1, 0, 0, 0, 0}, {-1, 0, 0, 0, 0, 0}, {0, 1, 0, 0, 0, 0}};
  LidarDecodeOptions options;
  options.sweep_period_s = 0.1;
  const auto decoded = DecodePointCloud2(kHeader, layout, VelodyneData(points), options);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const LidarScan& scan = decoded->scan;
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kAzimuth);
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_TRUE(scan.point_times_from_azimuth);
  EXPECT_EQ(scan.stamp, kHeader);
  EXPECT_EQ(scan.end, kHeader + 100'000'000);
  EXPECT_NEAR(scan.points[0].offset_ns, 0, 1);
  EXPECT_NEAR(scan.points[1].offset_ns, 25'000'000, 1);
  EXPECT_NEAR(scan.points[2].offset_ns, 50'000'000, 1);
  EXPECT_NEAR(scan.points[3].offset_ns, 75'000'000, 1);
}

TEST(PointCloud2Decode, WithoutTimeFieldDerivesOffsetsByTheConventionAsked) {
  PointCloud2Layout layout = VelodyneLayout(4);
  layout.fields.pop_back();  // no time field
  // Azimuths 0, 60, 180, -60 degrees: a counter-clockwise sweep from the first point meets them in this
  // order, at 0, 60, 180 and 300 degrees of its turn.
  const float c = 0.5f, s = std::sqrt(3.0f) / 2;
  const std::vector<TestPoint> points = {
      {1, 0, 0, 0, 0, 0}, {c, s, 0, 0, 0, 0}, {-1, 0, 0, 0, 0, 0}, {c, -s, 0, 0, 0, 0}};
  LidarDecodeOptions options;
  options.azimuth_convention = Reversed(kClockwiseFromFirstPoint);
  const auto decoded = DecodePointCloud2(kHeader, layout, VelodyneData(points), options);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const LidarScan& scan = decoded->scan;
  EXPECT_TRUE(scan.point_times_from_azimuth);
  EXPECT_NEAR(scan.points[0].offset_ns, 0, 1);
  EXPECT_NEAR(scan.points[1].offset_ns, 100'000'000 / 6.0, 2);
  EXPECT_NEAR(scan.points[2].offset_ns, 50'000'000, 2);
  EXPECT_NEAR(scan.points[3].offset_ns, 500'000'000 / 6.0, 2);
}

TEST(PointCloud2Decode, WithoutTimeFieldAndNoDerivationHasNoPointTimes) {
  PointCloud2Layout layout = VelodyneLayout(2);
  layout.fields.pop_back();
  const auto decoded =
      DecodePointCloud2(kHeader, layout, VelodyneData({{1, 0, 0, 0, 0, 0}, {0, 1, 0, 0, 0, 0}}), NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->point_time, PointTimeConvention::kNone);
  EXPECT_FALSE(decoded->scan.has_point_times);
  EXPECT_EQ(decoded->scan.stamp, kHeader);
  EXPECT_EQ(decoded->scan.end, kHeader + 100'000'000);  // stamp + sweep period
}

TEST(PointCloud2Decode, NonFinitePointsAreDroppedAndCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<TestPoint> points = {
      {nan, nan, nan, 0, 0, 0}, {1, 2, 3, 0, 0, 0.01f}, {inf, 0, 0, 0, 0, 0}, {4, 5, 6, 0, 0, nan}};
  const auto decoded = DecodePointCloud2(kHeader, VelodyneLayout(4), VelodyneData(points), NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->non_finite_points, 3);
  ASSERT_EQ(decoded->scan.points.size(), 1u);
  EXPECT_EQ(decoded->scan.points[0].x, 1);
}

TEST(PointCloud2Decode, RowStepPaddingAndWrongRowStepOnPackedData) {
  PointCloud2Layout layout = VelodyneLayout(2);
  layout.height = 2;
  layout.row_step = 50;  // 44 bytes of points + 6 of padding per row
  std::vector<std::uint8_t> data(100);
  const std::vector<std::uint8_t> row0 = VelodyneData({{1, 0, 0, 0, 0, 0}, {2, 0, 0, 0, 0, 0}});
  const std::vector<std::uint8_t> row1 = VelodyneData({{3, 0, 0, 0, 0, 0}, {4, 0, 0, 0, 0, 0}});
  std::copy(row0.begin(), row0.end(), data.begin());
  std::copy(row1.begin(), row1.end(), data.begin() + 50);
  auto decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  ASSERT_EQ(decoded->scan.points.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(decoded->scan.points[i].x, i + 1.0f);

  layout.row_step = 7;  // wrong, but the data is exactly width*height*point_step
  std::vector<std::uint8_t> packed = row0;
  packed.insert(packed.end(), row1.begin(), row1.end());
  decoded = DecodePointCloud2(kHeader, layout, packed, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->scan.points.size(), 4u);
}

TEST(PointCloud2Decode, BigEndianFloat64AndIntegerFields) {
  PointCloud2Layout layout;
  layout.height = 1;
  layout.width = 1;
  layout.is_bigendian = true;
  layout.point_step = 28;
  layout.row_step = 28;
  layout.fields = {{"x", 0, 8, 1},          {"y", 8, 8, 1},     {"z", 16, 7, 1},
                   {"intensity", 20, 2, 1}, {"ring", 22, 4, 1}, {"t", 24, 6, 1}};
  auto big_endian = [](auto value) {
    std::uint8_t bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));
    std::reverse(bytes, bytes + sizeof(value));
    return std::vector<std::uint8_t>(bytes, bytes + sizeof(value));
  };
  std::vector<std::uint8_t> data;
  for (const auto& part :
       {big_endian(1.5), big_endian(-2.25), big_endian(3.0f), big_endian(std::uint16_t{0xab00}),
        big_endian(std::uint16_t{42}), big_endian(std::uint32_t{123456})}) {
    data.insert(data.end(), part.begin(), part.end());
  }
  data[20] = 200;  // intensity is uint8 at byte 20; byte 21 is padding
  const auto decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  ASSERT_EQ(decoded->scan.points.size(), 1u);
  const LidarPoint& point = decoded->scan.points[0];
  EXPECT_EQ(point.x, 1.5f);
  EXPECT_EQ(point.y, -2.25f);
  EXPECT_EQ(point.z, 3.0f);
  EXPECT_EQ(point.intensity, 200.0f);
  EXPECT_EQ(point.ring, 42);
  EXPECT_EQ(point.offset_ns, 123456);
}

TEST(PointCloud2Decode, InconsistentLayoutsAreRefusedWithWhatWasExpected) {
  const std::vector<std::uint8_t> data = VelodyneData({{1, 2, 3, 0, 0, 0}, {1, 2, 3, 0, 0, 0}});
  PointCloud2Layout layout = VelodyneLayout(2);

  layout.width = 3;  // data holds 2 points
  auto decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("data size disagrees"), std::string::npos) << decoded.error();

  layout = VelodyneLayout(2);
  layout.fields[3].datatype = 9;
  decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("unknown datatype"), std::string::npos) << decoded.error();
  EXPECT_NE(decoded.error().find("intensity"), std::string::npos) << decoded.error();

  layout = VelodyneLayout(2);
  layout.fields[5].offset = 20;  // float32 at 20..24 of a 22-byte point
  decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("past point_step"), std::string::npos) << decoded.error();

  layout = VelodyneLayout(2);
  layout.fields[2].name = "w";
  decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("x, y or z"), std::string::npos) << decoded.error();

  layout = VelodyneLayout(2);
  layout.point_step = 0;
  layout.fields = {};
  decoded = DecodePointCloud2(kHeader, layout, data, NoAzimuth());
  ASSERT_FALSE(decoded.ok());
}

TEST(PointCloud2Decode, EmptyCloudAndTimesSpreadTooWide) {
  PointCloud2Layout layout = VelodyneLayout(0);
  auto decoded = DecodePointCloud2(kHeader, layout, {}, NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_TRUE(decoded->scan.points.empty());
  EXPECT_EQ(decoded->scan.stamp, kHeader);

  const std::vector<TestPoint> points = {{1, 0, 0, 0, 0, 0.0f}, {0, 1, 0, 0, 0, 3.0f}};  // 3 s apart
  decoded = DecodePointCloud2(kHeader, VelodyneLayout(2), VelodyneData(points), NoAzimuth());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_FALSE(decoded->scan.has_point_times);
  EXPECT_FALSE(decoded->point_times_dropped.empty());
  EXPECT_EQ(decoded->scan.points.size(), 2u);
}

}  // namespace
}  // namespace uf
