#include "odometry/io/rosbag/bag_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "odometry/io/rosbag/chunk_decompress.h"

namespace uf::bag {
namespace {

constexpr std::string_view kVersionLine = "#ROSBAG V2.0\n";
// Record headers hold a few short fields (op, conn, time, topic, sizes); a longer one is damage, refused
// before anything is allocated for it.
constexpr std::uint32_t kMaxHeaderLength = 1 << 20;
// Connection records carry the message definition text, chunk info records 8 bytes per connection.
constexpr std::uint32_t kMaxIndexRecordData = 16 << 20;

std::string_view AsText(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

BagFile::~BagFile() {
  if (fd_ >= 0) ::close(fd_);
}

Expected<std::unique_ptr<BagFile>> BagFile::Open(const std::filesystem::path& path) {
  std::unique_ptr<BagFile> bag(new BagFile(path));
  if (Status opened = bag->OpenFile(); !opened.ok()) return opened;
  if (Status indexed = bag->ReadIndex(); !indexed.ok()) return indexed;
  bag->position_ = bag->records_begin_;
  return bag;
}

Status BagFile::Error(std::uint64_t offset, const std::string& what) const {
  return Status::Error(path_.string() + ": record at offset " + std::to_string(offset) + ": " + what);
}

Status BagFile::ReadAt(std::uint64_t offset, std::span<std::uint8_t> out) const {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t got = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      return Status::Error(path_.string() + ": cannot read " + std::to_string(out.size()) +
                           " bytes at offset " + std::to_string(offset) +
                           (got < 0 ? ": " + std::string(std::strerror(errno)) : ""));
    }
    done += static_cast<std::size_t>(got);
  }
  return Status();
}

Status BagFile::OpenFile() {
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) return Status::Error("cannot open ROS bag " + path_.string() + ": " + std::strerror(errno));
  struct stat info {};
  if (::fstat(fd_, &info) != 0 || !S_ISREG(info.st_mode)) {
    return Status::Error(path_.string() + " is not a regular file");
  }
  file_size_ = static_cast<std::uint64_t>(info.st_size);

  // Version line.
  std::uint8_t version[kVersionLine.size()] = {};
  if (file_size_ < kVersionLine.size() || !ReadAt(0, version).ok() || AsText(version) != kVersionLine) {
    const std::string_view start = AsText(std::span(version, std::min<std::size_t>(file_size_, 12)));
    if (start.starts_with("#ROSBAG V")) {
      return Status::Error(path_.string() + ": unsupported ROS bag version '" + std::string(start.substr(8)) +
                           "' (only 2.0 is read; `rosbag fix` converts older bags)");
    }
    return Status::Error(path_.string() + " is not a ROS bag: it does not start with '#ROSBAG V2.0'");
  }

  // File header record: where the index starts and how many records it holds.
  const Expected<TopRecord> record = ReadTopRecord(kVersionLine.size(), file_size_);
  if (!record.ok()) return record.status();
  if (Status parsed = header_.Parse(header_bytes_); !parsed.ok()) {
    return Error(kVersionLine.size(), "file header: " + parsed.message());
  }
  const Expected<Op> op = header_.Operation();
  if (!op.ok() || *op != Op::kFileHeader) {
    return Error(kVersionLine.size(), "expected the file header record");
  }
  const Expected<std::uint64_t> index_position = header_.U64("index_pos");
  if (!index_position.ok()) return Error(kVersionLine.size(), "file header: " + index_position.error());
  if (const auto encryptor = header_.Field("encryptor");
      encryptor && !encryptor->empty() && *encryptor != "rosbag/NoEncryptor") {
    return Status::Error(path_.string() + ": encrypted bags are not supported (encryptor '" +
                         std::string(*encryptor) + "')");
  }
  const Expected<std::uint32_t> connection_count = header_.U32("conn_count");
  const Expected<std::uint32_t> chunk_count = header_.U32("chunk_count");
  if (!connection_count.ok()) return Error(kVersionLine.size(), "file header: " + connection_count.error());
  if (!chunk_count.ok()) return Error(kVersionLine.size(), "file header: " + chunk_count.error());
  connection_count_ = *connection_count;
  chunk_count_ = *chunk_count;
  records_begin_ = record->end;
  index_position_ = *index_position;
  if (index_position_ == 0) {
    return Status::Error(
        path_.string() +
        ": the bag has no index (its recording was interrupted?); `rosbag reindex` repairs it");
  }
  if (index_position_ < records_begin_ || index_position_ > file_size_) {  // == : an empty bag
    return Status::Error(path_.string() + ": the index should start at offset " +
                         std::to_string(index_position_) + " but the file has " + std::to_string(file_size_) +
                         " bytes (the bag is truncated or corrupt)");
  }
  return Status();
}

Expected<BagFile::TopRecord> BagFile::ReadTopRecord(std::uint64_t offset, std::uint64_t end) {
  std::uint8_t length_bytes[4];
  if (end < offset || end - offset < 8) return Error(offset, "record is cut off (file ends or index begins)");
  if (Status read = ReadAt(offset, length_bytes); !read.ok()) return read;
  const std::uint32_t header_length = LoadLittleEndian<std::uint32_t>(length_bytes);
  if (header_length > kMaxHeaderLength || header_length > end - offset - 8) {
    return Error(offset, "header length " + std::to_string(header_length) + " runs past the " +
                             std::to_string(end - offset - 8) + " bytes left");
  }
  header_bytes_.resize(header_length + 4);
  if (Status read = ReadAt(offset + 4, header_bytes_); !read.ok()) return read;
  TopRecord record;
  record.data_length = LoadLittleEndian<std::uint32_t>(header_bytes_.data() + header_length);
  header_bytes_.resize(header_length);
  record.data_offset = offset + 8 + header_length;
  if (record.data_length > end - record.data_offset) {
    return Error(offset, "data length " + std::to_string(record.data_length) + " runs past the " +
                             std::to_string(end - record.data_offset) + " bytes left");
  }
  record.end = record.data_offset + record.data_length;
  return record;
}

Status BagFile::AddConnection(const RecordHeader& header, std::span<const std::uint8_t> connection_header) {
  const Expected<std::uint32_t> id = header.U32("conn");
  if (!id.ok()) return Status::Error("connection record: " + id.error());
  if (connection_by_id_.contains(*id)) return Status();
  Connection connection;
  connection.id = *id;
  connection.topic = std::string(header.Field("topic").value_or(""));
  RecordHeader fields;  // the publisher's connection header: type, md5sum, message_definition, ...
  if (Status parsed = fields.Parse(connection_header); !parsed.ok()) {
    return Status::Error("connection header of topic '" + connection.topic + "': " + parsed.message());
  }
  connection.type = std::string(fields.Field("type").value_or(""));
  connection.md5sum = std::string(fields.Field("md5sum").value_or(""));
  if (connection.topic.empty()) connection.topic = std::string(fields.Field("topic").value_or(""));
  connection_by_id_.emplace(connection.id, connections_.size());
  connections_.push_back(std::move(connection));
  return Status();
}

Status BagFile::ReadIndex() {
  // Every record takes at least 8 bytes, so this loop ends with the file even if the counts are wrong.
  std::uint64_t offset = index_position_;
  for (std::uint64_t i = 0; i < std::uint64_t{connection_count_} + chunk_count_; ++i) {
    const Expected<TopRecord> record = ReadTopRecord(offset, file_size_);
    if (!record.ok()) return Status::Error(record.error() + " (index section cut off?)");
    if (Status parsed = header_.Parse(header_bytes_); !parsed.ok()) return Error(offset, parsed.message());
    const Expected<Op> op = header_.Operation();
    const bool is_connection = i < connection_count_;
    if (!op.ok() || *op != (is_connection ? Op::kConnection : Op::kChunkInfo)) {
      return Error(offset, is_connection ? "expected a connection record in the index"
                                         : "expected a chunk info record in the index");
    }
    if (record->data_length > kMaxIndexRecordData) {
      return Error(offset,
                   "index record of " + std::to_string(record->data_length) + " bytes is implausible");
    }
    if (is_connection) {
      record_data_.resize(record->data_length);
      if (Status read = ReadAt(record->data_offset, record_data_); !read.ok()) return read;
      if (Status added = AddConnection(header_, record_data_); !added.ok()) {
        return Error(offset, added.message());
      }
    } else {
      const Expected<std::uint64_t> chunk_position = header_.U64("chunk_pos");
      if (!chunk_position.ok()) return Error(offset, "chunk info: " + chunk_position.error());
      if (*chunk_position < records_begin_ || *chunk_position >= index_position_) {
        return Error(offset, "chunk info points to offset " + std::to_string(*chunk_position) +
                                 ", outside the chunk section");
      }
    }
    offset = record->end;
  }
  return Status();
}

Status BagFile::LoadChunk(const TopRecord& record) {
  const std::optional<std::string_view> compression = header_.Field("compression");
  const Expected<std::uint32_t> size = header_.U32("size");
  if (!compression || !size.ok()) {
    return Status::Error("chunk header: " +
                         (size.ok() ? std::string("missing field 'compression'") : size.error()));
  }
  if (*compression == "none") {
    if (*size != record.data_length) {
      return Status::Error("uncompressed chunk declares " + std::to_string(*size) + " bytes but holds " +
                           std::to_string(record.data_length));
    }
    if (chunk_.size() < record.data_length) chunk_.resize(record.data_length);
    if (Status read = ReadAt(record.data_offset, std::span(chunk_.data(), record.data_length)); !read.ok()) {
      return read;
    }
  } else if (*compression == "bz2" || *compression == "lz4") {
    if (compressed_.size() < record.data_length) compressed_.resize(record.data_length);
    const std::span<std::uint8_t> input(compressed_.data(), record.data_length);
    if (Status read = ReadAt(record.data_offset, input); !read.ok()) return read;
    Status decompressed =
        *compression == "bz2" ? DecompressBz2(input, *size, chunk_) : DecompressLz4(input, *size, chunk_);
    if (!decompressed.ok()) return decompressed;
  } else {
    return Status::Error("unknown chunk compression '" + std::string(*compression) +
                         "' (expected none, bz2 or lz4)");
  }
  chunk_size_ = *size;
  chunk_cursor_ = 0;
  return Status();
}

Expected<std::optional<MessageRecord>> BagFile::NextInChunk() {
  while (chunk_cursor_ < chunk_size_) {
    const std::size_t at = chunk_cursor_;
    auto chunk_error = [&](const std::string& what) {
      return Status::Error(path_.string() + ": chunk at offset " + std::to_string(chunk_offset_) + ", byte " +
                           std::to_string(at) + " of its " + std::to_string(chunk_size_) +
                           " decompressed bytes: " + what);
    };
    const Expected<RecordSpan> record = SplitRecord(std::span(chunk_.data() + at, chunk_size_ - at));
    if (!record.ok()) return chunk_error(record.error());
    if (Status parsed = header_.Parse(record->header); !parsed.ok()) return chunk_error(parsed.message());
    const Expected<Op> op = header_.Operation();
    if (!op.ok()) return chunk_error(op.error());
    chunk_cursor_ += record->size;
    if (*op == Op::kConnection) {
      if (Status added = AddConnection(header_, record->data); !added.ok()) {
        return chunk_error(added.message());
      }
      continue;
    }
    if (*op != Op::kMessageData) {
      return chunk_error("unexpected record op " + std::to_string(static_cast<int>(*op)) + " inside a chunk");
    }
    const Expected<std::uint32_t> connection = header_.U32("conn");
    const Expected<Stamp> time = header_.Time("time");
    if (!connection.ok() || !time.ok()) {
      return chunk_error(connection.ok() ? time.error() : connection.error());
    }
    if (!connection_by_id_.contains(*connection)) {
      return chunk_error("message of connection " + std::to_string(*connection) +
                         ", which the bag never defines");
    }
    return std::optional<MessageRecord>(MessageRecord{*connection, *time, record->data});
  }
  return std::optional<MessageRecord>();
}

Expected<std::optional<MessageRecord>> BagFile::Next() {
  while (true) {
    Expected<std::optional<MessageRecord>> message = NextInChunk();
    if (!message.ok() || message->has_value()) return message;
    if (position_ >= index_position_) return std::optional<MessageRecord>();  // the index follows the chunks

    const std::uint64_t offset = position_;
    const Expected<TopRecord> record = ReadTopRecord(offset, index_position_);
    if (!record.ok()) return record.status();
    if (Status parsed = header_.Parse(header_bytes_); !parsed.ok()) return Error(offset, parsed.message());
    const Expected<Op> op = header_.Operation();
    if (!op.ok()) return Error(offset, op.error());
    position_ = record->end;
    switch (*op) {
      case Op::kChunk:
        chunk_offset_ = offset;
        chunk_size_ = 0;
        if (Status loaded = LoadChunk(*record); !loaded.ok()) return Error(offset, loaded.message());
        break;
      case Op::kIndexData:
        break;  // per-chunk index: not needed when reading in file order
      case Op::kConnection: {
        if (record->data_length > kMaxIndexRecordData) {
          return Error(offset, "connection record is implausibly long");
        }
        record_data_.resize(record->data_length);
        if (Status read = ReadAt(record->data_offset, record_data_); !read.ok()) return read;
        if (Status added = AddConnection(header_, record_data_); !added.ok()) {
          return Error(offset, added.message());
        }
        break;
      }
      default:
        return Error(offset, "unexpected record op " + std::to_string(static_cast<int>(*op)) +
                                 " between chunks (expected a chunk or index data record)");
    }
  }
}

}  // namespace uf::bag
