#include "odometry/io/rosbag/bag_record.h"

namespace uf::bag {

Status RecordHeader::Parse(std::span<const std::uint8_t> bytes) {
  fields_.clear();
  std::size_t position = 0;
  while (position < bytes.size()) {
    if (bytes.size() - position < 4) {
      return Status::Error("header field length at byte " + std::to_string(position) + " is cut off");
    }
    const std::uint32_t length = LoadLittleEndian<std::uint32_t>(bytes.data() + position);
    position += 4;
    if (length > bytes.size() - position) {
      return Status::Error("header field of " + std::to_string(length) + " bytes at byte " +
                           std::to_string(position - 4) + " runs past the " + std::to_string(bytes.size()) +
                           "-byte header");
    }
    const std::string_view field(reinterpret_cast<const char*>(bytes.data() + position), length);
    const std::size_t equals = field.find('=');
    if (equals == std::string_view::npos) {
      return Status::Error("header field at byte " + std::to_string(position - 4) + " has no '='");
    }
    fields_.emplace_back(field.substr(0, equals), field.substr(equals + 1));
    position += length;
  }
  return Status();
}

std::optional<std::string_view> RecordHeader::Field(std::string_view name) const {
  for (const auto& [field_name, value] : fields_) {
    if (field_name == name) return value;
  }
  return std::nullopt;
}

Expected<Stamp> RecordHeader::Time(std::string_view name) const {
  const Expected<std::uint64_t> packed = U64(name);
  if (!packed.ok()) return packed.status();
  return RosTimeToStamp(static_cast<std::uint32_t>(*packed & 0xffffffffu),
                        static_cast<std::uint32_t>(*packed >> 32));
}

Expected<Op> RecordHeader::Operation() const {
  const Expected<std::uint8_t> op = U8("op");
  if (!op.ok()) return op.status();
  return static_cast<Op>(*op);
}

Expected<RecordSpan> SplitRecord(std::span<const std::uint8_t> bytes) {
  const std::size_t available = bytes.size();
  if (available < 4) return Status::Error("record header length is cut off");
  const std::uint64_t header_length = LoadLittleEndian<std::uint32_t>(bytes.data());
  if (header_length > available - 4 || available - 4 - header_length < 4) {
    return Status::Error("record header of " + std::to_string(header_length) + " bytes runs past the " +
                         std::to_string(available) + " bytes left");
  }
  const std::uint64_t data_length = LoadLittleEndian<std::uint32_t>(bytes.data() + 4 + header_length);
  if (data_length > available - 8 - header_length) {
    return Status::Error("record data of " + std::to_string(data_length) + " bytes runs past the " +
                         std::to_string(available - 8 - header_length) + " bytes left");
  }
  RecordSpan record;
  record.header = bytes.subspan(4, header_length);
  record.data = bytes.subspan(8 + header_length, data_length);
  record.size = 8 + header_length + data_length;
  return record;
}

}  // namespace uf::bag
