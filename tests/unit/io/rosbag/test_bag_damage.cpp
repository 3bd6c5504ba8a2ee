// Damaged bags: missing, not a bag, unindexed, truncated at every length, bytes corrupted inside chunks of
// every compression, single damaged messages. Each must give an error naming the file (or warnings), never a
// crash or a hang; and the record stream of intact bags must equal what librosbag itself reads.
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <random>

#include "odometry/io/rosbag/bag_file.h"
#include "odometry/io/rosbag/rosbag_reader.h"
#include "tests/unit/io/rosbag/bag_test_util.h"

namespace uf {
namespace {

using testing::BagCompression;
using testing::BagEntry;
using testing::ReadAll;
using testing::TempDir;

constexpr Stamp kT0 = 1'500'000'000'000'000'000;
constexpr Stamp kMs = 1'000'000;

std::vector<BagEntry> MixedBag(int count) {
  std::vector<BagEntry> entries;
  for (int i = 0; i < count; ++i) {
    const Stamp t = kT0 + i * 10 * kMs;
    entries.push_back({"/imu", t, testing::MakeImu(t, "imu", {0, 0, 9.81}, {0, 0, 0.1 * i})});
    // Distinct record times, so that librosbag's time-ordered View and the record order agree.
    if (i % 4 == 0) entries.push_back({"/points", t + 1000, testing::VelodyneCloud(t, 30 + i)});
    if (i % 5 == 0) {
      entries.push_back({"/fix", t + 2000, testing::MakeNavSatFix(t, "gps", 0, 42, -71, 5, {}, 0)});
    }
  }
  return entries;
}

std::string WriteMixedBag(const TempDir& dir, const std::string& name, BagCompression compression,
                          int count = 40) {
  const std::string path = dir.File(name);
  EXPECT_EQ(testing::WriteBag(path, MixedBag(count), compression, 4096), "");
  return path;
}

// Opens and drains (bounded); returns "" when everything was read, else the error. An error must name the
// file, and Next() must repeat it.
std::string OpenAndDrain(const std::string& path) {
  auto reader = OpenRosBag(path, {});
  if (!reader.ok()) {
    EXPECT_NE(reader.error().find(path), std::string::npos) << reader.error();
    return reader.error();
  }
  for (int i = 0; i < 100000; ++i) {
    auto next = (*reader)->Next();
    if (!next.ok()) {
      EXPECT_NE(next.error().find(path), std::string::npos) << next.error();
      auto again = (*reader)->Next();
      EXPECT_FALSE(again.ok());
      if (!again.ok()) {
        EXPECT_EQ(again.error(), next.error());
      }
      return next.error();
    }
    if (!next->has_value()) return "";
  }
  ADD_FAILURE() << "more than 100000 measurements from a small bag";
  return "hang";
}

TEST(RosBagDamage, MissingFileDirectoryAndNotABag) {
  TempDir dir;
  auto reader = OpenRosBag(dir.File("missing.bag"), {});
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("missing.bag"), std::string::npos) << reader.error();
  EXPECT_FALSE(OpenRosBag(dir.path(), {}).ok());
  const std::string text = dir.Write("text.bag", "this is not a bag at all, just some text\n");
  reader = OpenRosBag(text, {});
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("not a ROS bag"), std::string::npos) << reader.error();
  const std::string old = dir.Write("old.bag", std::string("#ROSBAG V1.2\n") + std::string(100, '\0'));
  reader = OpenRosBag(old, {});
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("1.2"), std::string::npos) << reader.error();
  EXPECT_FALSE(OpenRosBag(dir.Write("empty.bag", ""), {}).ok());
}

TEST(RosBagDamage, UnindexedBagIsAnErrorThatSaysSo) {
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "unindexed.bag", BagCompression::kNone);
  std::vector<std::uint8_t> bytes = testing::ReadBytes(path);
  const std::string field = "index_pos=";
  const auto at = std::search(bytes.begin(), bytes.end(), field.begin(), field.end());
  ASSERT_NE(at, bytes.end());
  std::fill(at + static_cast<std::ptrdiff_t>(field.size()),
            at + static_cast<std::ptrdiff_t>(field.size() + 8), 0);
  testing::WriteBytes(path, bytes);
  const std::string error = OpenAndDrain(path);
  EXPECT_NE(error.find("no index"), std::string::npos) << error;
}

class RosBagDamageEveryCompression : public ::testing::TestWithParam<BagCompression> {};

TEST_P(RosBagDamageEveryCompression, IntactBagMatchesLibrosbag) {
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "intact.bag", GetParam(), 60);
  std::string error;
  const auto expected = testing::ReadBagWithLibrosbag(path, &error);
  ASSERT_EQ(error, "");
  auto bag = bag::BagFile::Open(path);
  ASSERT_TRUE(bag.ok()) << bag.error();
  std::size_t index = 0;
  while (true) {
    auto record = (*bag)->Next();
    ASSERT_TRUE(record.ok()) << record.error();
    if (!record->has_value()) break;
    ASSERT_LT(index, expected.size());
    const auto& connection =
        *std::find_if((*bag)->connections().begin(), (*bag)->connections().end(),
                      [&](const bag::Connection& c) { return c.id == (*record)->connection; });
    EXPECT_EQ(connection.topic, expected[index].topic);
    EXPECT_EQ(connection.type, expected[index].type);
    EXPECT_EQ((*record)->time, expected[index].record_time_ns);
    EXPECT_TRUE(std::equal((*record)->data.begin(), (*record)->data.end(), expected[index].bytes.begin(),
                           expected[index].bytes.end()));
    ++index;
  }
  EXPECT_EQ(index, expected.size());
  EXPECT_EQ(OpenAndDrain(path), "");
}

TEST_P(RosBagDamageEveryCompression, TruncatedAtEveryLengthIsAnError) {
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "whole.bag", GetParam(), 12);
  const std::vector<std::uint8_t> whole = testing::ReadBytes(path);
  const std::string cut_path = dir.File("cut.bag");
  for (std::size_t length = 0; length < whole.size(); length += 1 + length / 512) {
    testing::WriteBytes(cut_path, std::vector<std::uint8_t>(whole.begin(), whole.begin() + length));
    EXPECT_NE(OpenAndDrain(cut_path), "") << "cut at " << length << " of " << whole.size();
  }
}

TEST_P(RosBagDamageEveryCompression, CorruptedChunkBytesGiveAnErrorOrWarnings) {
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "whole.bag", GetParam(), 20);
  const std::vector<std::uint8_t> whole = testing::ReadBytes(path);
  const testing::TopLevelRecord chunk = testing::FirstChunk(whole);
  const std::string damaged_path = dir.File("damaged.bag");
  std::mt19937 random(7);
  int errors = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<std::uint8_t> damaged = whole;
    const int flips = 1 + static_cast<int>(random() % 4);
    for (int f = 0; f < flips; ++f) {
      // Mostly inside the first chunk's data, sometimes anywhere (headers, index).
      const std::size_t at =
          trial % 4 == 0 ? random() % damaged.size() : chunk.data_offset + random() % chunk.data_size;
      damaged[at] ^= static_cast<std::uint8_t>(1 + random() % 255);
    }
    testing::WriteBytes(damaged_path, damaged);
    if (!OpenAndDrain(damaged_path).empty()) ++errors;
  }
  EXPECT_GT(errors, 0);
}

TEST_P(RosBagDamageEveryCompression, DamageInsideAChunkNamesTheChunk) {
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "whole.bag", GetParam(), 20);
  std::vector<std::uint8_t> bytes = testing::ReadBytes(path);
  const testing::TopLevelRecord chunk = testing::FirstChunk(bytes);
  if (GetParam() == BagCompression::kNone) {
    std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(chunk.data_offset), 4,
                0xff);  // first record's header length
  } else {
    bytes[chunk.data_offset + chunk.data_size / 2] ^= 0x5a;  // the checksum no longer matches
  }
  testing::WriteBytes(path, bytes);
  const std::string error = OpenAndDrain(path);
  EXPECT_NE(error.find("offset " + std::to_string(chunk.offset)), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(Compressions, RosBagDamageEveryCompression,
                         ::testing::Values(BagCompression::kNone, BagCompression::kBz2,
                                           BagCompression::kLz4));

TEST(RosBagDamage, OversizedLz4BlockIsRefusedBeforeDecompression) {
  // roslz4 would copy such a block past the end of its buffer.
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "lz4.bag", BagCompression::kLz4, 20);
  std::vector<std::uint8_t> bytes = testing::ReadBytes(path);
  const testing::TopLevelRecord chunk = testing::FirstChunk(bytes);
  const std::uint32_t huge_block = 0x00ffffff;
  ASSERT_GT(chunk.data_size, 11u);
  std::memcpy(&bytes[chunk.data_offset + 7], &huge_block,
              4);  // the first block size, after the 7-byte header
  testing::WriteBytes(path, bytes);
  const std::string error = OpenAndDrain(path);
  EXPECT_NE(error.find("lz4"), std::string::npos) << error;
}

TEST(RosBagDamage, UncompressedChunkWithTwoSizesIsAnError) {
  // librosbag asserts on this one.
  TempDir dir;
  const std::string path = WriteMixedBag(dir, "raw.bag", BagCompression::kNone, 20);
  std::vector<std::uint8_t> bytes = testing::ReadBytes(path);
  const std::string field = "size=";
  const auto at = std::search(bytes.begin(), bytes.end(), field.begin(), field.end());
  ASSERT_NE(at, bytes.end());
  at[static_cast<std::ptrdiff_t>(field.size())] ^= 0x01;
  testing::WriteBytes(path, bytes);
  const std::string error = OpenAndDrain(path);
  EXPECT_NE(error.find("declares"), std::string::npos) << error;
}

// Header stamp `stamp`, recorded 1 ms later.
BagEntry EntryAt(const std::string& topic, Stamp stamp, testing::RosMessage message) {
  return BagEntry{topic, stamp + kMs, std::move(message)};
}

TEST(RosBagDamage, DamagedMessagesAreSkippedAndCounted) {
  TempDir dir;
  const std::string path = dir.File("damaged.bag");
  std::vector<BagEntry> entries;
  const Stamp t = kT0;
  entries.push_back(EntryAt("/points", t, testing::VelodyneCloud(t, 10)));
  testing::RosMessage wrong_size = testing::VelodyneCloud(t + 100 * kMs, 10);
  wrong_size = testing::MakePointCloud2(t + 100 * kMs, "v", 1, 11, {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}},
                                        false, 22, 22 * 11, std::vector<std::uint8_t>(220));
  entries.push_back(EntryAt("/points", t + 100 * kMs, wrong_size));
  entries.push_back(
      EntryAt("/points", t + 200 * kMs,
              testing::MakePointCloud2(t + 200 * kMs, "v", 1, 1, {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 13}},
                                       false, 12, 12, std::vector<std::uint8_t>(12))));
  std::vector<std::uint8_t> nan_cloud(12 * 3, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan_cloud[12], &nan, 4);
  std::memcpy(&nan_cloud[24], &nan, 4);
  entries.push_back(
      EntryAt("/points", t + 300 * kMs,
              testing::MakePointCloud2(t + 300 * kMs, "v", 1, 3, {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}},
                                       false, 12, 36, nan_cloud)));
  entries.push_back(
      EntryAt("/points", t + 400 * kMs, testing::MakeRaw("sensor_msgs/PointCloud2", {1, 2, 3})));
  entries.push_back(
      EntryAt("/odom", t, testing::MakeRaw("nav_msgs/Odometry", std::vector<std::uint8_t>(40, 0))));
  entries.push_back(EntryAt("/odom", t, testing::MakeOdometry(t, "o", "b", {1, 0, 0}, {})));
  ASSERT_EQ(testing::WriteBag(path, entries), "");

  DatasetOptions options;
  options.derive_point_times_from_azimuth = false;
  auto reader = OpenRosBag(path, options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  const std::vector<Measurement> all = ReadAll(**reader);
  ASSERT_EQ(all.size(), 3u);  // the good cloud, the NaN cloud (one point left), the good odometry
  EXPECT_EQ(std::get<LidarScan>(all[1].data).points.size(), 1u);
  std::map<std::string, std::int64_t> warnings;
  for (const ReadWarning& warning : (*reader)->warnings()) {
    warnings[warning.stream + ": " + warning.what.substr(0, warning.what.find(" ("))] += warning.count;
  }
  EXPECT_EQ(
      warnings["/points: PointCloud2 data size disagrees with row_step*height and width*height*point_step"],
      1);
  EXPECT_EQ(warnings["/points: PointCloud2 field has an unknown datatype, expected 1..8"], 1);
  EXPECT_EQ(warnings["/points: NaN points dropped"], 2);
  EXPECT_EQ(warnings["/points: message is too short for a sensor_msgs/PointCloud2"], 1);
  EXPECT_EQ(warnings["/odom: message is too short for a nav_msgs/Odometry"], 1);
  EXPECT_EQ(warnings.size(), 5u);
}

}  // namespace
}  // namespace uf
