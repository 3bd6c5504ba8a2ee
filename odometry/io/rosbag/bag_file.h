// Streams the message records of a ROS1 bag (format 2.0) in file order with one chunk in memory at a time.
// Opening reads the version line, the file header and the index section at the end of the file (connection
// and chunk info records), so a cut-off or unindexed bag fails at once; chunks are read, decompressed and
// checked as the stream reaches them.
//
// This is our own parser of the format rather than librosbag's reader: librosbag trusts the offsets and
// lengths in the file (an index offset or a record length past the end of a chunk makes it read out of
// bounds, a raw chunk whose two sizes differ trips an assert) and roslz4 overflows its block buffer on an
// oversized lz4 block. Here every length is checked against the bytes that hold it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "odometry/io/rosbag/bag_record.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::bag {

struct Connection {
  std::uint32_t id = 0;
  std::string topic;
  std::string type;  // ROS message type, "sensor_msgs/Imu"
  std::string md5sum;
};

struct MessageRecord {
  std::uint32_t connection = 0;        // a Connection::id
  Stamp time = 0;                      // record (receive) time
  std::span<const std::uint8_t> data;  // the serialized message; valid until the next call to Next()
};

class BagFile {
 public:
  // Errors name the path and the offset of the record that is wrong.
  static Expected<std::unique_ptr<BagFile>> Open(const std::filesystem::path& path);
  ~BagFile();
  BagFile(const BagFile&) = delete;
  BagFile& operator=(const BagFile&) = delete;

  // Connections of the index, in the order the index lists them (the order they first appeared).
  const std::vector<Connection>& connections() const { return connections_; }
  std::uint64_t file_size() const { return file_size_; }

  // The next message record in file order, std::nullopt after the last. An error is unrecoverable damage.
  Expected<std::optional<MessageRecord>> Next();

 private:
  // Where a record outside the chunks lies: its header bytes are in header_bytes_.
  struct TopRecord {
    std::uint64_t data_offset = 0;
    std::uint32_t data_length = 0;
    std::uint64_t end = 0;  // offset just past the record
  };

  explicit BagFile(std::filesystem::path path) : path_(std::move(path)) {}
  Status OpenFile();
  Status ReadIndex();
  Status ReadAt(std::uint64_t offset, std::span<std::uint8_t> out) const;
  Expected<TopRecord> ReadTopRecord(std::uint64_t offset, std::uint64_t end);
  Status AddConnection(const RecordHeader& header, std::span<const std::uint8_t> connection_header);
  Status LoadChunk(const TopRecord& record);
  Expected<std::optional<MessageRecord>> NextInChunk();
  Status Error(std::uint64_t offset, const std::string& what) const;

  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t file_size_ = 0;
  std::uint64_t records_begin_ = 0;     // first record after the file header
  std::uint64_t index_position_ = 0;    // start of the index section (connection and chunk info records)
  std::uint32_t connection_count_ = 0;  // connection records in the index section
  std::uint32_t chunk_count_ = 0;       // chunk info records after them
  std::vector<Connection> connections_;
  std::unordered_map<std::uint32_t, std::size_t> connection_by_id_;

  // Streaming state: the next top-level record, and the decompressed chunk being walked.
  std::uint64_t position_ = 0;
  std::uint64_t chunk_offset_ = 0;
  std::size_t chunk_size_ = 0;
  std::size_t chunk_cursor_ = 0;
  std::vector<std::uint8_t> chunk_;       // capacity kept between chunks
  std::vector<std::uint8_t> compressed_;  // capacity kept between chunks
  std::vector<std::uint8_t> header_bytes_;
  std::vector<std::uint8_t> record_data_;
  RecordHeader header_;
};

}  // namespace uf::bag
