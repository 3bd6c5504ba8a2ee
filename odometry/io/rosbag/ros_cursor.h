// Reading ROS1 serialized messages: fixed-size fields are little endian and packed, strings and variable
// arrays are a uint32 element count followed by the elements, fixed arrays are the elements alone. Every read
// is bounds-checked: after the first read past the end, ok() is false and every later read gives zeros.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "odometry/io/rosbag/bag_record.h"
#include "odometry/types/stamp.h"

namespace uf::bag {

class RosCursor {
 public:
  explicit RosCursor(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  bool ok() const { return ok_; }
  std::size_t remaining() const { return bytes_.size() - position_; }

  template <typename T>
  T Read() {
    const std::span<const std::uint8_t> raw = Take(sizeof(T));
    return raw.empty() ? T{} : LoadLittleEndian<T>(raw.data());
  }
  double ReadFloat64() { return Read<double>(); }

  std::span<const std::uint8_t> Take(std::size_t count) {
    if (!ok_ || count > remaining()) {
      ok_ = false;
      return {};
    }
    const std::span<const std::uint8_t> taken = bytes_.subspan(position_, count);
    position_ += count;
    return taken;
  }
  void Skip(std::size_t count) { Take(count); }
  void SkipFloat64s(std::size_t count) { Take(count * sizeof(double)); }

  // uint32 element count, then `element_size` bytes per element.
  std::span<const std::uint8_t> TakeArray(std::size_t element_size, std::uint32_t* count = nullptr) {
    const std::uint32_t elements = Read<std::uint32_t>();
    if (count != nullptr) *count = elements;
    return Take(std::size_t{elements} * element_size);
  }
  std::string_view ReadString() {
    const std::span<const std::uint8_t> text = TakeArray(1);
    return {reinterpret_cast<const char*>(text.data()), text.size()};
  }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;
  bool ok_ = true;
};

// std_msgs/Header: uint32 seq, time stamp (uint32 sec, uint32 nsec), string frame_id.
struct RosHeader {
  Stamp stamp = 0;
  std::string_view frame_id;  // a view into the message bytes
};

inline RosHeader ReadRosHeader(RosCursor& cursor) {
  RosHeader header;
  cursor.Read<std::uint32_t>();  // seq
  const std::uint32_t sec = cursor.Read<std::uint32_t>();
  const std::uint32_t nsec = cursor.Read<std::uint32_t>();
  header.stamp = RosTimeToStamp(sec, nsec);
  header.frame_id = cursor.ReadString();
  return header;
}

}  // namespace uf::bag
