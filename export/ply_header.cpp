#include "export/ply_header.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <sstream>
#include <utility>

namespace uf::exporting {
namespace {

struct TypeName {
  const char* name;
  PlyType type;
};
// Both spellings of the PLY types (the original names and the sized ones).
constexpr std::array<TypeName, 16> kTypeNames = {{{"char", PlyType::kInt8},
                                                  {"int8", PlyType::kInt8},
                                                  {"uchar", PlyType::kUint8},
                                                  {"uint8", PlyType::kUint8},
                                                  {"short", PlyType::kInt16},
                                                  {"int16", PlyType::kInt16},
                                                  {"ushort", PlyType::kUint16},
                                                  {"uint16", PlyType::kUint16},
                                                  {"int", PlyType::kInt32},
                                                  {"int32", PlyType::kInt32},
                                                  {"uint", PlyType::kUint32},
                                                  {"uint32", PlyType::kUint32},
                                                  {"float", PlyType::kFloat32},
                                                  {"float32", PlyType::kFloat32},
                                                  {"double", PlyType::kFloat64},
                                                  {"float64", PlyType::kFloat64}}};

bool ParseType(const std::string& word, PlyType* type) {
  for (const TypeName& t : kTypeNames)
    if (word == t.name) {
      *type = t.type;
      return true;
    }
  return false;
}

// One header line without its end (\n or \r\n); false at the end of the stream or past the byte limit.
bool ReadLine(std::istream& in, std::string* line, std::size_t* consumed) {
  line->clear();
  char c;
  while (*consumed < kMaxPlyHeaderBytes && in.get(c)) {
    ++*consumed;
    if (c == '\n') {
      if (!line->empty() && line->back() == '\r') line->pop_back();
      return true;
    }
    line->push_back(c);
  }
  return false;
}

template <typename T>
T Load(const char* bytes, bool swap) {
  std::array<char, sizeof(T)> raw;
  std::memcpy(raw.data(), bytes, sizeof(T));
  if (swap) std::reverse(raw.begin(), raw.end());
  T value;
  std::memcpy(&value, raw.data(), sizeof(T));
  return value;
}

}  // namespace

std::size_t PlyTypeSize(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool PlyElement::has_list() const {
  return std::any_of(properties.begin(), properties.end(), [](const PlyProperty& p) { return p.is_list; });
}

double DecodePlyValue(const char* bytes, PlyType type, bool swap) {
  switch (type) {
    case PlyType::kInt8:
      return Load<std::int8_t>(bytes, swap);
    case PlyType::kUint8:
      return Load<std::uint8_t>(bytes, swap);
    case PlyType::kInt16:
      return Load<std::int16_t>(bytes, swap);
    case PlyType::kUint16:
      return Load<std::uint16_t>(bytes, swap);
    case PlyType::kInt32:
      return Load<std::int32_t>(bytes, swap);
    case PlyType::kUint32:
      return Load<std::uint32_t>(bytes, swap);
    case PlyType::kFloat32:
      return Load<float>(bytes, swap);
    case PlyType::kFloat64:
      return Load<double>(bytes, swap);
  }
  return 0;
}

Expected<PlyHeader> ParsePlyHeader(std::istream& in, const std::string& name) {
  PlyHeader header;
  std::size_t consumed = 0;
  std::string line;
  if (!ReadLine(in, &line, &consumed) || line != "ply")
    return Status::Error(name + ": not a PLY file (the first line must be 'ply')");
  bool have_format = false;
  for (int number = 2;; ++number) {
    if (!ReadLine(in, &line, &consumed))
      return Status::Error(name + ": PLY header has no 'end_header' line" +
                           (consumed >= kMaxPlyHeaderBytes ? " within its first 1 MiB" : ""));
    const std::string where =
        name + ": PLY header line " + std::to_string(number) + " '" + line.substr(0, 80) + "': ";
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string format, version;
      words >> format >> version;
      if (format == "ascii")
        header.format = PlyFormat::kAscii;
      else if (format == "binary_little_endian")
        header.format = PlyFormat::kBinaryLittleEndian;
      else if (format == "binary_big_endian")
        header.format = PlyFormat::kBinaryBigEndian;
      else
        return Status::Error(where + "unknown format '" + format + "'");
      if (version != "1.0") return Status::Error(where + "unsupported version '" + version + "'");
      have_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      std::string count;
      words >> element.name >> count;
      const char* end = count.data() + count.size();
      const auto [ptr, error] = std::from_chars(count.data(), end, element.count);
      if (element.name.empty() || count.empty() || error != std::errc() || ptr != end)
        return Status::Error(where + "expected 'element NAME COUNT' with a non-negative integer count");
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) return Status::Error(where + "property before any element");
      PlyElement& element = header.elements.back();
      PlyProperty property;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type;
        words >> count_type >> type;
        property.is_list = true;
        PlyType ignored;
        if (!ParseType(count_type, &ignored))
          return Status::Error(where + "unknown list count type '" + count_type + "'");
      }
      words >> property.name;
      if (!ParseType(type, &property.type)) return Status::Error(where + "unknown type '" + type + "'");
      if (property.name.empty()) return Status::Error(where + "property without a name");
      property.offset = element.record_bytes;
      if (!property.is_list) element.record_bytes += PlyTypeSize(property.type);
      element.properties.push_back(std::move(property));
    } else {
      return Status::Error(where + "unknown keyword '" + keyword + "'");
    }
  }
  if (!have_format) return Status::Error(name + ": PLY header has no 'format' line");
  header.header_bytes = consumed;
  return header;
}

}  // namespace uf::exporting
