#include "odometry/io/folders/lidar_record_file.h"

#include <bit>
#include <cstring>

namespace uf {
namespace {

static_assert(std::endian::native == std::endian::little, "records are little-endian, as is the host");

constexpr char kMagic[4] = {'U', 'F', 'L', 'S'};
constexpr std::uint32_t kHasPointTimes = 1u << 0;
constexpr std::uint32_t kPointTimesFromAzimuth = 1u << 1;
constexpr std::uint32_t kHasRing = 1u << 2;
constexpr std::uint32_t kKnownFlags = kHasPointTimes | kPointTimesFromAzimuth | kHasRing;

template <typename T>
void Put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

template <typename T>
T Get(const char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

}  // namespace

std::string EncodeLidarRecord(const LidarScan& scan) {
  std::string out;
  out.reserve(kLidarRecordHeaderBytes + kLidarRecordPointBytes * scan.points.size());
  out.append(kMagic, 4);
  Put<std::uint32_t>(out, (scan.has_point_times ? kHasPointTimes : 0) |
                              (scan.point_times_from_azimuth ? kPointTimesFromAzimuth : 0) |
                              (scan.has_ring ? kHasRing : 0));
  Put<std::int64_t>(out, scan.stamp);
  Put<std::int64_t>(out, scan.end);
  Put<std::uint64_t>(out, scan.points.size());
  for (const LidarPoint& point : scan.points) {
    Put(out, point.x);
    Put(out, point.y);
    Put(out, point.z);
    Put(out, point.intensity);
    Put(out, point.ring);
    Put(out, point.offset_ns);
  }
  return out;
}

Expected<LidarRecordReader> LidarRecordReader::Open(const std::filesystem::path& path) {
  LidarRecordReader reader;
  reader.path_ = path.string();
  std::error_code error;
  reader.size_ = std::filesystem::file_size(path, error);
  if (error) return Status::Error(reader.path_ + ": cannot read the file size: " + error.message());
  reader.in_ = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*reader.in_) return Status::Error(reader.path_ + ": cannot open file");
  return reader;
}

Status LidarRecordReader::Error(std::uint64_t offset, const std::string& what) const {
  return Status::Error(path_ + ": byte offset " + std::to_string(offset) + ": " + what);
}

Expected<std::optional<LidarScan>> LidarRecordReader::Next() {
  if (offset_ == size_) return std::optional<LidarScan>();
  const std::uint64_t start = offset_;
  const std::uint64_t left = size_ - offset_;
  if (left < kLidarRecordHeaderBytes)
    return Error(start, "truncated record: " + std::to_string(left) + " bytes left, a record header takes " +
                            std::to_string(kLidarRecordHeaderBytes));
  char header[kLidarRecordHeaderBytes];
  if (!in_->read(header, sizeof(header))) return Error(start, "read error");
  if (std::memcmp(header, kMagic, 4) != 0) return Error(start, "not a scan record (magic is not \"UFLS\")");
  const auto flags = Get<std::uint32_t>(header + 4);
  if (flags & ~kKnownFlags) return Error(start + 4, "unknown flags " + std::to_string(flags));
  LidarScan scan;
  scan.has_point_times = flags & kHasPointTimes;
  scan.point_times_from_azimuth = flags & kPointTimesFromAzimuth;
  scan.has_ring = flags & kHasRing;
  scan.stamp = Get<std::int64_t>(header + 8);
  scan.end = Get<std::int64_t>(header + 16);
  if (scan.end < scan.stamp)
    return Error(start + 16,
                 "end_ns " + std::to_string(scan.end) + " is before stamp_ns " + std::to_string(scan.stamp));
  const auto count = Get<std::uint64_t>(header + 24);
  const std::uint64_t body = left - kLidarRecordHeaderBytes;
  if (count > body / kLidarRecordPointBytes)
    return Error(start + 24,
                 "point_count " + std::to_string(count) + " needs " +
                     (count > body ? std::string("more") : std::to_string(count * kLidarRecordPointBytes)) +
                     " bytes, only " + std::to_string(body) + " are left (truncated or corrupt)");
  std::string bytes(count * kLidarRecordPointBytes, '\0');
  if (!in_->read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    return Error(start + kLidarRecordHeaderBytes, "read error");
  scan.points.resize(count);
  const char* p = bytes.data();
  for (LidarPoint& point : scan.points) {
    point.x = Get<float>(p);
    point.y = Get<float>(p + 4);
    point.z = Get<float>(p + 8);
    point.intensity = Get<float>(p + 12);
    point.ring = Get<std::uint16_t>(p + 16);
    point.offset_ns = Get<std::int32_t>(p + 18);
    p += kLidarRecordPointBytes;
  }
  offset_ = start + kLidarRecordHeaderBytes + bytes.size();
  return std::optional<LidarScan>(std::move(scan));
}

}  // namespace uf
