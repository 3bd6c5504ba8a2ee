// PCD and KITTI .bin files: every DATA kind, the recognised fields, and damaged files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "odometry/io/folders/lzf.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/folders/folder_fixtures.h"

namespace uf {
namespace {

using testing::TempDir;
using testing::XyziPoint;

const std::vector<XyziPoint> kPoints = {{1.5f, -2.25f, 0.125f, 7}, {-3, 4, 5, 0.5f}, {0.1f, 0.2f, 0.3f, 255}};

void ExpectPoints(const LidarScan& scan, const std::vector<XyziPoint>& expected) {
  ASSERT_EQ(scan.points.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(scan.points[i].x, expected[i].x) << i;
    EXPECT_EQ(scan.points[i].y, expected[i].y) << i;
    EXPECT_EQ(scan.points[i].z, expected[i].z) << i;
    EXPECT_EQ(scan.points[i].intensity, expected[i].intensity) << i;
  }
}

std::filesystem::path Seed(const char* name) {
  return std::filesystem::path(UF_PCD_CORPUS) / (std::string(name) + ".pcd");
}

// The error of reading `bytes` as a PCD file (fails the test when it reads).
std::string PcdError(const std::string& bytes) {
  TempDir dir;
  testing::WriteBytes(dir.File("bad.pcd"), bytes);
  auto scan = ReadPcdFile(dir.File("bad.pcd"));
  EXPECT_FALSE(scan.ok()) << "read " << (scan ? scan->points.size() : 0) << " points";
  return scan ? "" : scan.error();
}

TEST(PcdFile, ReadsAsciiBinaryAndCompressed) {
  for (const char* data : {"ascii", "binary", "binary_compressed"}) {
    TempDir dir;
    testing::WriteBytes(dir.File("scan.pcd"), testing::XyziPcd(kPoints, data));
    PointCloudFileInfo info;
    auto scan = ReadPcdFile(dir.File("scan.pcd"), &info);
    ASSERT_TRUE(scan.ok()) << data << ": " << scan.error();
    ExpectPoints(*scan, kPoints);
    EXPECT_FALSE(scan->has_point_times);
    EXPECT_FALSE(scan->has_ring);
    EXPECT_EQ(info.points_in_file, 3);
    EXPECT_EQ(info.point_time, PointTimeConvention::kNone);
  }
}

TEST(PcdFile, ReadsPclWrittenSeedsWithRingAndRelativeTime) {
  // Written by PCL's PCDWriter (binary_compressed with real LZF back references): x y z intensity f32,
  // ring u16, time f32 = 0.1 * i / 120 s.
  for (const char* name : {"velodyne_ascii", "velodyne_binary", "velodyne_binary_compressed"}) {
    PointCloudFileInfo info;
    auto scan = ReadPcdFile(Seed(name), &info);
    ASSERT_TRUE(scan.ok()) << scan.error();
    ASSERT_EQ(scan->points.size(), 120u) << name;
    EXPECT_TRUE(scan->has_ring);
    EXPECT_TRUE(scan->has_point_times);
    EXPECT_EQ(info.point_time_field, "time");
    EXPECT_EQ(info.point_time, PointTimeConvention::kRelativeSeconds);
    EXPECT_EQ(scan->stamp, 0);
    EXPECT_NEAR(scan->end, 0.1 * 119 / 120 * 1e9, 100);
    for (int i = 0; i < 120; ++i) {
      const float angle = 2 * M_PI * i / 120;
      EXPECT_FLOAT_EQ(scan->points[i].x, 10 * std::cos(angle)) << name << " " << i;
      EXPECT_EQ(scan->points[i].ring, i % 4);
      EXPECT_EQ(scan->points[i].intensity, i % 7);
      EXPECT_NEAR(scan->points[i].offset_ns, 0.1 * i / 120 * 1e9, 100);
    }
  }
  for (const char* name : {"xyz_organized_ascii", "xyz_organized_binary_compressed"}) {
    auto scan = ReadPcdFile(Seed(name));
    ASSERT_TRUE(scan.ok()) << scan.error();
    ASSERT_EQ(scan->points.size(), 60u);
    EXPECT_EQ(scan->points[59].x, 59);
    EXPECT_EQ(scan->points[59].y, 4);
  }
}

TEST(PcdFile, RecognisesOusterAndAbsoluteTimes) {
  TempDir dir;
  // Ouster: t uint32 ns relative; ring uint8.
  std::string ouster = testing::PcdHeaderText("x y z t ring", "4 4 4 4 1", "F F F U U", 2, "ascii") +
                       "1 2 3 500 7\n4 5 6 100 9\n";
  testing::WriteBytes(dir.File("ouster.pcd"), ouster);
  PointCloudFileInfo info;
  auto scan = ReadPcdFile(dir.File("ouster.pcd"), &info);
  ASSERT_TRUE(scan.ok()) << scan.error();
  EXPECT_EQ(info.point_time, PointTimeConvention::kRelativeNanoseconds);
  EXPECT_EQ(scan->stamp, 100);  // the earliest point
  EXPECT_EQ(scan->end, 500);
  EXPECT_EQ(scan->points[0].offset_ns, 400);
  EXPECT_EQ(scan->points[1].offset_ns, 0);
  EXPECT_EQ(scan->points[1].ring, 9);

  // Hesai: timestamp float64 absolute seconds; Livox: the same field in nanoseconds.
  testing::WriteBytes(dir.File("hesai.pcd"),
                      testing::PcdHeaderText("x y z timestamp", "4 4 4 8", "F F F F", 2, "ascii") +
                          "1 2 3 1700000000.25\n4 5 6 1700000000.3\n");
  scan = ReadPcdFile(dir.File("hesai.pcd"), &info);
  ASSERT_TRUE(scan.ok()) << scan.error();
  EXPECT_EQ(info.point_time, PointTimeConvention::kAbsoluteSeconds);
  EXPECT_LE(std::llabs(scan->stamp - 1'700'000'000'250'000'000), 1000);  // float64 seconds: ~0.2 us steps
  EXPECT_NEAR(scan->points[1].offset_ns, 50000000, 1000);
  testing::WriteBytes(dir.File("livox.pcd"),
                      testing::PcdHeaderText("x y z timestamp", "4 4 4 8", "F F F F", 1, "ascii") +
                          "1 2 3 1700000000250000000\n");
  scan = ReadPcdFile(dir.File("livox.pcd"), &info);
  ASSERT_TRUE(scan.ok()) << scan.error();
  EXPECT_EQ(info.point_time, PointTimeConvention::kAbsoluteNanoseconds);
  EXPECT_LE(std::llabs(scan->stamp - 1'700'000'000'250'000'000), 1000);
}

TEST(PcdFile, DropsNonFinitePointsAndCountsThem) {
  TempDir dir;
  std::vector<XyziPoint> points = kPoints;
  points.push_back({NAN, 1, 2, 3});
  points.push_back({1, INFINITY, 2, 3});
  for (const char* data : {"binary", "ascii"}) {
    testing::WriteBytes(dir.File("nan.pcd"), testing::XyziPcd(points, data));
    PointCloudFileInfo info;
    auto scan = ReadPcdFile(dir.File("nan.pcd"), &info);
    ASSERT_TRUE(scan.ok()) << scan.error();
    ExpectPoints(*scan, kPoints);
    EXPECT_EQ(info.dropped_non_finite, 2);
    EXPECT_EQ(info.points_in_file, 5);
  }
}

TEST(PcdFile, ReadsTheSharedLidarCameraScan) {
  const std::string data = testing::SharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent: skipping the recorded lidar-camera-pair scan";
  PointCloudFileInfo info;
  auto scan = ReadPcdFile(data + "/lidar-camera-pair/scan.pcd", &info);
  ASSERT_TRUE(scan.ok()) << scan.error();
  EXPECT_EQ(info.points_in_file, 78238);
  EXPECT_GT(scan->points.size(), 78000u);
  EXPECT_EQ(scan->points[0].x, 21.647913f);  // the first line: 21.647913 0.19822195 -1.8524752 11
  EXPECT_EQ(scan->points[0].intensity, 11);
  float max_intensity = 0;
  for (const LidarPoint& point : scan->points) max_intensity = std::max(max_intensity, point.intensity);
  EXPECT_GT(max_intensity, 11);
}

TEST(PcdFile, RejectsDamagedHeadersWithTheReason) {
  const std::string good = testing::XyziPcd(kPoints, "binary");
  auto replaced = [&](const std::string& from, const std::string& to) {
    return testing::Replaced(good, from, to);
  };
  EXPECT_NE(PcdError(replaced("POINTS 3", "POINTS 4")).find("POINTS 4 disagrees with WIDTH 3"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("WIDTH 3", "WIDTH 2")).find("disagrees"), std::string::npos);
  EXPECT_NE(PcdError(replaced("FIELDS x y z intensity", "FIELDS x y q intensity")).find("no field 'z'"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("SIZE 4 4 4 4", "SIZE 4 4 4")).find("SIZE has 3 entries for 4 FIELDS"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("TYPE F F F F", "TYPE F F F X")).find("TYPE must be I, U or F"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("SIZE 4 4 4 4", "SIZE 4 4 4 3")).find("SIZE must be 1, 2, 4 or 8"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("DATA binary", "DATA zipped")).find("unknown DATA kind"), std::string::npos);
  EXPECT_NE(PcdError(replaced("DATA binary\n", "")).find("no complete DATA line"), std::string::npos);
  EXPECT_NE(PcdError("").find("not a PCD file"), std::string::npos);
  // Huge declared sizes fail on the size check, before any allocation.
  const std::string huge =
      testing::Replaced(replaced("POINTS 3", "POINTS 2000000000"), "WIDTH 3", "WIDTH 2000000000");
  EXPECT_NE(PcdError(huge).find("binary data is truncated: 2000000000 points"), std::string::npos);
  EXPECT_NE(PcdError(replaced("WIDTH 3", "WIDTH 99999999999999")).find("WIDTH is not a count"),
            std::string::npos);
  EXPECT_NE(PcdError(replaced("COUNT 1 1 1 1", "COUNT 1 1 1 4000000000")).find("COUNT must be"),
            std::string::npos);
}

TEST(PcdFile, RejectsTruncatedAndCorruptData) {
  const std::string binary = testing::XyziPcd(kPoints, "binary");
  std::string error = PcdError(binary.substr(0, binary.size() - 5));
  EXPECT_NE(error.find("bad.pcd: byte offset"), std::string::npos) << error;
  EXPECT_NE(error.find("binary data is truncated: 3 points of 16 bytes need 48 bytes, the file has 43"),
            std::string::npos)
      << error;

  const std::string ascii = testing::XyziPcd(kPoints, "ascii");
  error = PcdError(ascii.substr(0, ascii.rfind('\n', ascii.size() - 2) + 1));
  EXPECT_NE(error.find("ascii data is truncated: 2 of 3 points"), std::string::npos) << error;
  error = PcdError(testing::Replaced(ascii, "-2.25", "-2.x5"));
  EXPECT_NE(error.find("bad.pcd:12: field 'y' value '-2.x5' is not a number"), std::string::npos) << error;
  EXPECT_NE(PcdError(testing::Replaced(ascii, " 0.5\n", "\n")).find(":13: point 1 has too few values"),
            std::string::npos);

  const std::string compressed = testing::XyziPcd(kPoints, "binary_compressed");
  error = PcdError(compressed.substr(0, compressed.size() - 3));
  EXPECT_NE(error.find("binary_compressed data is truncated"), std::string::npos) << error;
  std::string wrong_size = compressed;
  wrong_size[wrong_size.find("DATA binary_compressed\n") + 23 + 4] = 47;  // uncompressed size low byte
  EXPECT_NE(PcdError(wrong_size).find("uncompressed size 47 disagrees"), std::string::npos);
  std::string corrupt = compressed;
  corrupt[corrupt.find("DATA binary_compressed\n") + 23 + 8] =
      static_cast<char>(0xe0);  // reference before start
  EXPECT_NE(PcdError(corrupt).find("LZF decompression failed"), std::string::npos);
}

TEST(Lzf, DecodesBackReferencesAndRejectsBadOnes) {
  // "abc" as a literal run, then a back reference of length 2 + 4 = 6 at distance 3: "abcabcabc".
  const std::uint8_t stream[] = {2, 'a', 'b', 'c', (4 << 5) | 0, 2};
  std::uint8_t out[16];
  EXPECT_EQ(LzfDecompress(stream, sizeof(stream), out, sizeof(out)), 9u);
  EXPECT_EQ(std::string(reinterpret_cast<char*>(out), 9), "abcabcabc");
  EXPECT_EQ(LzfDecompress(stream, sizeof(stream), out, 8), std::nullopt);       // output too small
  EXPECT_EQ(LzfDecompress(stream, sizeof(stream) - 1, out, 16), std::nullopt);  // truncated token
  const std::uint8_t before_start[] = {0, 'a', (1 << 5) | 0, 5};
  EXPECT_EQ(LzfDecompress(before_start, sizeof(before_start), out, 16), std::nullopt);
}

TEST(KittiBin, ReadsPointsAndRejectsPartialRecords) {
  TempDir dir;
  testing::WriteBytes(dir.File("000000.bin"), testing::PackXyzi(kPoints));
  auto scan = ReadKittiBin(dir.File("000000.bin"));
  ASSERT_TRUE(scan.ok()) << scan.error();
  ExpectPoints(*scan, kPoints);

  testing::WriteBytes(dir.File("000001.bin"), testing::PackXyzi(kPoints).substr(0, 40));
  scan = ReadKittiBin(dir.File("000001.bin"));
  ASSERT_FALSE(scan.ok());
  EXPECT_NE(scan.error().find("000001.bin: size 40 bytes is not a multiple of 16"), std::string::npos)
      << scan.error();
  EXPECT_FALSE(ReadKittiBin(dir.File("missing.bin")).ok());
}

TEST(AzimuthPointTimes, SweepClockwiseFromBehind) {
  LidarScan scan;
  scan.stamp = 1000;
  scan.points = {
      {-10, 1e-4f, 0}, {0, 10, 0}, {10, 0, 0}, {0, -10, 0}, {-10, -1e-4f, 0}};  // behind, left, ...
  DerivePointTimesFromAzimuth(scan, 100'000'000);
  EXPECT_TRUE(scan.has_point_times);
  EXPECT_TRUE(scan.point_times_from_azimuth);
  EXPECT_EQ(scan.end, 1000 + 100'000'000);
  EXPECT_NEAR(scan.points[0].offset_ns, 0, 1000);           // start: behind
  EXPECT_NEAR(scan.points[1].offset_ns, 25'000'000, 1000);  // left (+y) a quarter later: clockwise
  EXPECT_NEAR(scan.points[2].offset_ns, 50'000'000, 1000);  // forward half-way
  EXPECT_NEAR(scan.points[3].offset_ns, 75'000'000, 1000);
  EXPECT_NEAR(scan.points[4].offset_ns, 100'000'000, 1000);  // end: behind again
}

}  // namespace
}  // namespace uf
