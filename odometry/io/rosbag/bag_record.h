// ROS1 bag format 2.0 records (http://wiki.ros.org/Bags/Format/2.0). A bag is the line "#ROSBAG V2.0\n"
// followed by records; every record is
//   uint32 header_len | header (header_len bytes) | uint32 data_len | data (data_len bytes)
// and a header is a sequence of fields, each  uint32 field_len | name '=' value  (value binary, little
// endian). Everything here checks lengths against the bytes it is given and never reads past them.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::bag {

// The `op` field of a record header.
enum class Op : std::uint8_t {
  kMessageData = 0x02,
  kFileHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07,
};

// Little-endian loads from unaligned bytes (the bag format and ROS serialization are little endian).
template <typename T>
T LoadLittleEndian(const std::uint8_t* bytes) {
  static_assert(std::endian::native == std::endian::little, "big-endian hosts are not supported");
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// ROS time as packed in bag headers and messages: uint32 sec, uint32 nsec -> ns since the epoch.
inline Stamp RosTimeToStamp(std::uint32_t sec, std::uint32_t nsec) {
  return static_cast<Stamp>(sec) * kNanosecondsPerSecond + static_cast<Stamp>(nsec);
}

// The fields of one record header, as views into the bytes it was parsed from (keep those alive).
class RecordHeader {
 public:
  // Replaces the fields with those in `bytes`. The error says which field overruns or lacks its '='.
  Status Parse(std::span<const std::uint8_t> bytes);

  std::optional<std::string_view> Field(std::string_view name) const;

  // A fixed-size integer field; the error names the field and says what size was expected.
  Expected<std::uint8_t> U8(std::string_view name) const { return Fixed<std::uint8_t>(name); }
  Expected<std::uint32_t> U32(std::string_view name) const { return Fixed<std::uint32_t>(name); }
  Expected<std::uint64_t> U64(std::string_view name) const { return Fixed<std::uint64_t>(name); }
  Expected<Stamp> Time(std::string_view name) const;  // packed uint32 sec | uint32 nsec
  Expected<Op> Operation() const;

 private:
  template <typename T>
  Expected<T> Fixed(std::string_view name) const {
    const std::optional<std::string_view> value = Field(name);
    if (!value) return Status::Error("missing header field '" + std::string(name) + "'");
    if (value->size() != sizeof(T)) {
      return Status::Error("header field '" + std::string(name) + "' has " + std::to_string(value->size()) +
                           " bytes, expected " + std::to_string(sizeof(T)));
    }
    return LoadLittleEndian<T>(reinterpret_cast<const std::uint8_t*>(value->data()));
  }

  std::vector<std::pair<std::string_view, std::string_view>> fields_;
};

// One record found in a byte range: its header bytes and data bytes (views into that range).
struct RecordSpan {
  std::span<const std::uint8_t> header;
  std::span<const std::uint8_t> data;
  std::size_t size = 0;  // bytes the record occupies: 4 + header + 4 + data
};

// Splits the record starting at bytes[0]; the error says which length runs past the end of `bytes`.
Expected<RecordSpan> SplitRecord(std::span<const std::uint8_t> bytes);

}  // namespace uf::bag
