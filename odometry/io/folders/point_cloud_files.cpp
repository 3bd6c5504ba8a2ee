// PCD decoding: the header is parsed and checked against the file size by pcd_header.cpp, then the body is
// decoded here, without PCL. PCL 1.13's PCDReader is not safe on damaged files: it allocates
// WIDTH*HEIGHT*point_step bytes before comparing with the file size (2.4 GB for a 150-byte file declaring
// 200M points), reports success for ASCII lines with missing or non-numeric values (leaving zeros), and
// prints to stderr; and linking pcl_io drags in VTK, whose CMake targets need MPI.
#include "odometry/io/folders/point_cloud_files.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "odometry/io/folders/lzf.h"
#include "odometry/io/folders/pcd_decode.h"
#include "odometry/io/folders/pcd_header.h"
#include "odometry/io/folders/xz_file.h"
#include "odometry/io/text_table.h"
#include "odometry/types/azimuth_convention.h"

namespace uf {
namespace {

static_assert(std::endian::native == std::endian::little, "the binary readers assume a little-endian host");

Expected<std::string> ReadWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Status::Error(path.string() + ": read error");
  return std::move(buffer).str();
}

int LineOf(std::string_view text, std::size_t offset) {
  int line = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) line += text[i] == '\n';
  return line;
}

// Parses one ASCII value into its binary form at `out`.
bool ParseAsciiValue(std::string_view text, const PcdField& field, char* out) {
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (field.type == 'F') {
    if (field.size == 4) {
      float value = 0;
      auto [stop, error] = std::from_chars(begin, end, value);
      if (error != std::errc() || stop != end) return false;
      std::memcpy(out, &value, 4);
    } else {
      double value = 0;
      auto [stop, error] = std::from_chars(begin, end, value);
      if (error != std::errc() || stop != end) return false;
      std::memcpy(out, &value, 8);
    }
    return true;
  }
  if (field.type == 'U') {
    std::uint64_t value = 0;
    auto [stop, error] = std::from_chars(begin, end, value);
    if (error != std::errc() || stop != end) return false;
    if (field.size < 8 && value >> (8 * field.size) != 0) return false;
    std::memcpy(out, &value, field.size);  // little-endian: the low bytes
    return true;
  }
  std::int64_t value = 0;
  auto [stop, error] = std::from_chars(begin, end, value);
  if (error != std::errc() || stop != end) return false;
  const std::int64_t limit = field.size == 8 ? std::numeric_limits<std::int64_t>::max()
                                             : (std::int64_t{1} << (8 * field.size - 1)) - 1;
  if (value > limit || value < -limit - 1) return false;
  std::memcpy(out, &value, field.size);
  return true;
}

// Turns the ASCII body into packed binary points (the layout of DATA binary).
Expected<std::string> PackAscii(const PcdHeader& header, std::string_view file, const std::string& path) {
  std::string packed(header.points * header.point_step, '\0');
  const int first_line = LineOf(file, header.data_offset);
  std::size_t offset = header.data_offset;
  std::uint64_t point = 0;
  for (int line = first_line; offset < file.size(); ++line) {
    std::size_t end = file.find('\n', offset);
    if (end == std::string_view::npos) end = file.size();
    const std::string_view text = file.substr(offset, end - offset);
    offset = end + 1;
    std::size_t i = 0;
    auto next_token = [&]() {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < text.size() && text[j] != ' ' && text[j] != '\t' && text[j] != '\r') ++j;
      std::string_view token = text.substr(i, j - i);
      i = j;
      return token;
    };
    std::string_view token = next_token();
    if (token.empty()) continue;  // blank line
    const std::string where = path + ":" + std::to_string(line) + ": ";
    if (point == header.points)
      return Status::Error(where + "more data lines than the header's POINTS " +
                           std::to_string(header.points));
    char* out = packed.data() + point * header.point_step;
    for (const PcdField& field : header.fields) {
      for (int c = 0; c < field.count; ++c, token = next_token()) {
        if (token.empty())
          return Status::Error(where + "point " + std::to_string(point) + " has too few values (" +
                               std::to_string(header.values_per_point()) + " expected)");
        if (!ParseAsciiValue(token, field, out + field.offset + c * field.size))
          return Status::Error(where + "field '" + field.name + "' value " + QuotedForError(token) +
                               " is not a " + (field.type == 'F' ? "number" : "integer of its SIZE"));
      }
    }
    if (!token.empty())
      return Status::Error(where + "point " + std::to_string(point) + " has more than " +
                           std::to_string(header.values_per_point()) + " values");
    ++point;
  }
  if (point != header.points)
    return Status::Error(path + ": ascii data is truncated: " + std::to_string(point) + " of " +
                         std::to_string(header.points) + " points present");
  return packed;
}

}  // namespace

Expected<LidarScan> ReadPcdFile(const std::filesystem::path& path, PointCloudFileInfo* info) {
  const std::string name = path.string();
  auto file = ReadWholeFile(path);
  if (!file) return file.status();
  auto header = ParsePcdHeader(*file, name);
  if (!header) return header.status();
  const std::string_view data = std::string_view(*file).substr(header->data_offset);
  if (Status s = CheckPcdDataSize(*header, data, name); !s.ok()) return s;

  PcdLayout layout;  // where each field's values lie in `body`
  std::string_view body;
  std::string decoded;
  switch (header->data) {
    case PcdDataKind::kAscii: {
      auto packed = PackAscii(*header, *file, name);
      if (!packed) return packed.status();
      decoded = std::move(*packed);
      body = decoded;
      layout = PcdLayout::PointMajor(*header);
      break;
    }
    case PcdDataKind::kBinary:
      body = data;  // trailing bytes (PCL pads files to a page) are ignored
      layout = PcdLayout::PointMajor(*header);
      break;
    case PcdDataKind::kBinaryCompressed: {
      // Two little-endian uint32 sizes, then LZF data; uncompressed, each field's values are contiguous.
      const std::uint64_t size = header->points * static_cast<std::uint64_t>(header->point_step);
      decoded.resize(size);
      if (size > 0) {
        std::uint32_t compressed = 0;
        std::memcpy(&compressed, data.data(), 4);
        const std::optional<std::size_t> produced =
            LzfDecompress(reinterpret_cast<const std::uint8_t*>(data.data()) + 8, compressed,
                          reinterpret_cast<std::uint8_t*>(decoded.data()), size);
        if (produced != size)
          return Status::Error(
              name + ": byte offset " + std::to_string(header->data_offset + 8) +
              ": binary_compressed data is corrupt (LZF decompression " +
              (produced ? "gave " + std::to_string(*produced) + " of " + std::to_string(size) + " bytes)"
                        : std::string("failed)")));
      }
      body = decoded;
      layout = PcdLayout::FieldMajor(*header);
      break;
    }
  }
  return DecodePcdPoints(*header, layout, body, name, info);
}

Expected<LidarScan> ReadKittiBin(const std::filesystem::path& path, PointCloudFileInfo* info) {
  const std::string name = path.string();
  auto file = path.extension() == ".xz" ? ReadXzFile(path) : ReadWholeFile(path);
  if (!file) return file.status();
  constexpr std::size_t kPointBytes = 16;  // float32 x, y, z, intensity
  if (file->size() % kPointBytes != 0)
    return Status::Error(name + ": size " + std::to_string(file->size()) +
                         " bytes is not a multiple of 16 (float32 x y z intensity per point); truncated?");
  const std::size_t count = file->size() / kPointBytes;
  LidarScan scan;
  scan.points.reserve(count);
  std::int64_t dropped = 0;
  for (std::size_t i = 0; i < count; ++i) {
    float values[4];
    std::memcpy(values, file->data() + i * kPointBytes, kPointBytes);
    if (!std::isfinite(values[0]) || !std::isfinite(values[1]) || !std::isfinite(values[2]) ||
        !std::isfinite(values[3])) {
      ++dropped;
      continue;
    }
    LidarPoint& point = scan.points.emplace_back();
    point.x = values[0];
    point.y = values[1];
    point.z = values[2];
    point.intensity = values[3];
  }
  if (info) {
    *info = PointCloudFileInfo{};
    info->points_in_file = static_cast<std::int64_t>(count);
    info->dropped_non_finite = dropped;
  }
  return scan;
}

void DerivePointTimesFromAzimuth(LidarScan& scan, Stamp sweep_period) {
  DeriveAzimuthPointTimes(scan, sweep_period, kClockwiseFromBehind);
}

}  // namespace uf
