// Helpers shared by the ROS bag reader tests (ReadAll: tests/support/read_all.h): Velodyne-like clouds, and
// a walk over the top-level records of a bag file (to aim damage at a chunk).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/rosbag/bag_record.h"
#include "tests/support/read_all.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/io/rosbag/ros_bag_fixtures.h"

namespace uf::testing {

// A Velodyne-style cloud: x y z intensity float32, ring uint16, time float32 s after the stamp (22 bytes).
inline RosMessage VelodyneCloud(std::int64_t stamp_ns, int points, float time_step_s = 1e-4f) {
  std::vector<std::uint8_t> data(static_cast<std::size_t>(points) * 22);
  for (int i = 0; i < points; ++i) {
    const float values[4] = {1.0f + i, 2.0f, 3.0f, static_cast<float>(i % 256)};
    const std::uint16_t ring = static_cast<std::uint16_t>(i % 32);
    const float time = i * time_step_s;
    std::memcpy(&data[i * 22], values, 16);
    std::memcpy(&data[i * 22 + 16], &ring, 2);
    std::memcpy(&data[i * 22 + 18], &time, 4);
  }
  return MakePointCloud2(
      stamp_ns, "velodyne", 1, points,
      {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}, {"intensity", 12, 7}, {"ring", 16, 4}, {"time", 18, 7}}, false,
      22, 22 * points, std::move(data));
}

inline std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  const std::string text = ReadText(path);
  return {text.begin(), text.end()};
}

inline void WriteBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

struct TopLevelRecord {
  std::size_t offset = 0;
  int op = -1;
  std::size_t data_offset = 0;
  std::size_t data_size = 0;
};

// The records after the version line, in file order (stops at the first one that does not parse).
inline std::vector<TopLevelRecord> TopLevelRecords(const std::vector<std::uint8_t>& bag) {
  std::vector<TopLevelRecord> records;
  std::size_t offset = 13;
  while (offset < bag.size()) {
    const auto record = bag::SplitRecord(std::span(bag).subspan(offset));
    if (!record.ok()) break;
    bag::RecordHeader header;
    if (!header.Parse(record->header).ok()) break;
    const auto op = header.U8("op");
    records.push_back({offset, op.ok() ? *op : -1, static_cast<std::size_t>(record->data.data() - bag.data()),
                       record->data.size()});
    offset += record->size;
  }
  return records;
}

inline TopLevelRecord FirstChunk(const std::vector<std::uint8_t>& bag) {
  for (const TopLevelRecord& record : TopLevelRecords(bag)) {
    if (record.op == 0x05) return record;
  }
  ADD_FAILURE() << "no chunk in the bag";
  return {};
}

}  // namespace uf::testing
