#include "odometry/io/folders/pcd_header.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "odometry/io/text_table.h"

namespace uf {
namespace {

// Limits far above any real scan that keep a corrupt header from asking for absurd sizes.
constexpr std::size_t kMaxFields = 256;
constexpr int kMaxCount = 1 << 16;
constexpr int kMaxPointStep = 1 << 20;
constexpr std::uint64_t kMaxPoints = std::numeric_limits<std::int32_t>::max();

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
  return tokens;
}

std::optional<std::uint64_t> ParseUnsigned(std::string_view text) {
  std::uint64_t value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

class HeaderParser {
 public:
  explicit HeaderParser(const std::string& path) : path_(path) {}

  Status Error(const std::string& what) const {
    return Status::Error(path_ + ": header line " + std::to_string(line_) + ": " + what);
  }

  // One header line (without its end of line); sets done() after the DATA line.
  Status Line(std::string_view line) {
    ++line_;
    const std::vector<std::string_view> tokens = Tokens(line);
    if (tokens.empty() || tokens[0].front() == '#') return {};
    const std::string_view key = tokens[0];
    const std::vector<std::string_view> values(tokens.begin() + 1, tokens.end());
    if (key == "VERSION") return {};
    if (key == "FIELDS" || key == "COLUMNS") return Fields(values);
    if (key == "SIZE") return PerField(values, key, sizes_);
    if (key == "TYPE") return PerField(values, key, types_);
    if (key == "COUNT") return PerField(values, key, counts_);
    if (key == "WIDTH") return Number(values, key, width_);
    if (key == "HEIGHT") return Number(values, key, height_);
    if (key == "POINTS") return Number(values, key, points_);
    if (key == "VIEWPOINT") return Viewpoint(values);
    if (key == "DATA") return Data(values);
    return Error("unknown header entry " + QuotedForError(key));
  }

  bool done() const { return done_; }

  // Combines the entries into a header once the DATA line has been read.
  Expected<PcdHeader> Finish(std::size_t data_offset) {
    if (fields_.empty()) return Error("no FIELDS line before DATA");
    if (sizes_.empty()) return Error("no SIZE line before DATA");
    if (types_.empty()) return Error("no TYPE line before DATA");
    if (!width_) return Error("no WIDTH line before DATA");
    PcdHeader header;
    header.data = data_;
    header.data_offset = data_offset;
    for (std::size_t i = 0; i < fields_.size(); ++i) {
      PcdField field;
      field.name = std::string(fields_[i]);
      if (Status s = FieldLayout(i, field); !s.ok()) return s;
      field.offset = header.point_step;
      header.point_step += field.size * field.count;
      if (header.point_step > kMaxPointStep)
        return Error("a point would take more than " + std::to_string(kMaxPointStep) + " bytes");
      header.fields.push_back(std::move(field));
    }
    header.width = *width_;
    header.height = height_.value_or(1);
    if (header.height != 0 && header.width > kMaxPoints / header.height)
      return Error("WIDTH " + std::to_string(header.width) + " * HEIGHT " + std::to_string(header.height) +
                   " is more than " + std::to_string(kMaxPoints) + " points");
    header.points = points_.value_or(header.width * header.height);
    if (header.points != header.width * header.height)
      return Error("POINTS " + std::to_string(header.points) + " disagrees with WIDTH " +
                   std::to_string(header.width) + " * HEIGHT " + std::to_string(header.height));
    for (const char* axis : {"x", "y", "z"}) {
      const PcdField* field = header.Find(axis);
      if (field == nullptr) return Error(std::string("no field '") + axis + "' in FIELDS");
      if (field->type != 'F' || field->count != 1)
        return Error(std::string("field '") + axis + "' must be a single float (TYPE F, COUNT 1)");
    }
    return header;
  }

 private:
  Status Fields(const std::vector<std::string_view>& values) {
    if (!fields_.empty()) return Error("FIELDS given twice");
    if (values.empty()) return Error("FIELDS names no field");
    if (values.size() > kMaxFields) return Error("more than " + std::to_string(kMaxFields) + " FIELDS");
    fields_ = values;
    return {};
  }

  Status PerField(const std::vector<std::string_view>& values, std::string_view key,
                  std::vector<std::string_view>& out) {
    if (!out.empty()) return Error(std::string(key) + " given twice");
    if (fields_.empty()) return Error(std::string(key) + " before FIELDS");
    if (values.size() != fields_.size())
      return Error(std::string(key) + " has " + std::to_string(values.size()) + " entries for " +
                   std::to_string(fields_.size()) + " FIELDS");
    out = values;
    return {};
  }

  Status Number(const std::vector<std::string_view>& values, std::string_view key,
                std::optional<std::uint64_t>& out) {
    if (out) return Error(std::string(key) + " given twice");
    if (values.size() != 1) return Error(std::string(key) + " needs one number");
    out = ParseUnsigned(values[0]);
    if (!out || *out > kMaxPoints)
      return Error(std::string(key) + " is not a count up to " + std::to_string(kMaxPoints) + ": " +
                   QuotedForError(values[0]));
    return {};
  }

  Status Viewpoint(const std::vector<std::string_view>& values) {
    if (values.size() != 7) return Error("VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
    for (std::string_view value : values) {
      double number = 0;
      auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
      if (error != std::errc() || end != value.data() + value.size() || !std::isfinite(number))
        return Error("VIEWPOINT value is not a number: " + QuotedForError(value));
    }
    return {};
  }

  Status Data(const std::vector<std::string_view>& values) {
    if (values.size() != 1) return Error("DATA needs one of ascii, binary, binary_compressed");
    if (values[0] == "ascii") {
      data_ = PcdDataKind::kAscii;
    } else if (values[0] == "binary") {
      data_ = PcdDataKind::kBinary;
    } else if (values[0] == "binary_compressed") {
      data_ = PcdDataKind::kBinaryCompressed;
    } else {
      return Error("unknown DATA kind " + QuotedForError(values[0]) + " (ascii, binary or binary_compressed)");
    }
    done_ = true;
    return {};
  }

  Status FieldLayout(std::size_t i, PcdField& field) const {
    const std::string name = "field '" + field.name + "'";
    const std::optional<std::uint64_t> size = ParseUnsigned(sizes_[i]);
    if (!size || (*size != 1 && *size != 2 && *size != 4 && *size != 8))
      return Error(name + ": SIZE must be 1, 2, 4 or 8, found " + QuotedForError(sizes_[i]));
    field.size = static_cast<int>(*size);
    if (types_[i] != "I" && types_[i] != "U" && types_[i] != "F")
      return Error(name + ": TYPE must be I, U or F, found " + QuotedForError(types_[i]));
    field.type = types_[i][0];
    if (field.type == 'F' && field.size != 4 && field.size != 8)
      return Error(name + ": a float (TYPE F) must have SIZE 4 or 8, found " + std::to_string(field.size));
    field.count = 1;
    if (!counts_.empty()) {
      const std::optional<std::uint64_t> count = ParseUnsigned(counts_[i]);
      if (!count || *count < 1 || *count > static_cast<std::uint64_t>(kMaxCount))
        return Error(name + ": COUNT must be 1.." + std::to_string(kMaxCount) + ", found " +
                     QuotedForError(counts_[i]));
      field.count = static_cast<int>(*count);
    }
    return {};
  }

  const std::string& path_;
  int line_ = 0;
  bool done_ = false;
  std::vector<std::string_view> fields_, sizes_, types_, counts_;
  std::optional<std::uint64_t> width_, height_, points_;
  PcdDataKind data_ = PcdDataKind::kAscii;
};

}  // namespace

const PcdField* PcdHeader::Find(std::string_view name) const {
  for (const PcdField& field : fields)
    if (field.name == name) return &field;
  return nullptr;
}

int PcdHeader::values_per_point() const {
  int values = 0;
  for (const PcdField& field : fields) values += field.count;
  return values;
}

Expected<PcdHeader> ParsePcdHeader(std::string_view file_start, const std::string& path) {
  HeaderParser parser(path);
  std::size_t offset = 0;
  while (offset < file_start.size() && offset < kMaxPcdHeaderBytes) {
    const std::size_t end = file_start.find('\n', offset);
    if (end == std::string_view::npos) break;
    std::string_view line = file_start.substr(offset, end - offset);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find('\0') != std::string_view::npos) return parser.Error("NUL byte in the header");
    offset = end + 1;
    if (Status s = parser.Line(line); !s.ok()) return s;
    if (parser.done()) return parser.Finish(offset);
  }
  return Status::Error(path + ": not a PCD file: no complete DATA line in the first " +
                       std::to_string(std::min(file_start.size(), kMaxPcdHeaderBytes)) + " bytes");
}

Status CheckPcdDataSize(const PcdHeader& header, std::string_view data, const std::string& path) {
  const std::string at = path + ": byte offset " + std::to_string(header.data_offset) + ": ";
  const std::uint64_t needed = header.points * static_cast<std::uint64_t>(header.point_step);
  switch (header.data) {
    case PcdDataKind::kAscii: {
      // Every value takes at least one character and one separator.
      const std::uint64_t minimum = header.points * static_cast<std::uint64_t>(header.values_per_point()) * 2;
      if (minimum > data.size() + 1)
        return Status::Error(at + "ascii data of " + std::to_string(data.size()) + " bytes cannot hold the " +
                             std::to_string(header.points) + " points the header declares");
      return {};
    }
    case PcdDataKind::kBinary:
      if (needed > data.size())
        return Status::Error(at + "binary data is truncated: " + std::to_string(header.points) +
                             " points of " + std::to_string(header.point_step) + " bytes need " +
                             std::to_string(needed) + " bytes, the file has " + std::to_string(data.size()));
      return {};
    case PcdDataKind::kBinaryCompressed:
      break;
  }
  if (header.points == 0) return {};
  if (data.size() < 8) return Status::Error(at + "binary_compressed data is missing its two size words");
  std::uint32_t compressed = 0, uncompressed = 0;
  std::memcpy(&compressed, data.data(), 4);  // little-endian, as PCL writes them
  std::memcpy(&uncompressed, data.data() + 4, 4);
  if (uncompressed != needed)
    return Status::Error(at + "binary_compressed uncompressed size " + std::to_string(uncompressed) +
                         " disagrees with " + std::to_string(header.points) + " points of " +
                         std::to_string(header.point_step) + " bytes");
  if (compressed > data.size() - 8)
    return Status::Error(at + "binary_compressed data is truncated: " + std::to_string(compressed) +
                         " compressed bytes declared, " + std::to_string(data.size() - 8) + " present");
  // LZF expands at most ~100x (a 3-byte back reference yields up to 264 bytes).
  if (uncompressed > static_cast<std::uint64_t>(compressed) * 100 + 1024)
    return Status::Error(at + "binary_compressed sizes are implausible: " + std::to_string(compressed) +
                         " bytes cannot expand to " + std::to_string(uncompressed));
  return {};
}

}  // namespace uf
