// Parsing of a PLY header (http://paulbourke.net/dataformats/ply/): the format line, the elements with
// their counts and scalar properties, up to `end_header`. Used by the 3DGS splat reader. Bounded: the
// header may hold at most kMaxPlyHeaderBytes bytes, and a count must be a plain non-negative integer; what
// the counts promise is checked against the file size by the caller before anything is allocated.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "odometry/types/status.h"

namespace uf::exporting {

inline constexpr std::size_t kMaxPlyHeaderBytes = 1 << 20;

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::size_t PlyTypeSize(PlyType type);

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;    // `property list ...`: variable length, unsupported by the splat reader
  std::size_t offset = 0;  // byte offset inside a binary record (meaningless after a list property)
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t record_bytes = 0;  // sum of the scalar property sizes (binary formats)
  bool has_list() const;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kBinaryLittleEndian;
  std::vector<PlyElement> elements;
  std::size_t header_bytes = 0;  // bytes up to and including the `end_header` line
};

// Reads the header from the start of `in`; leaves `in` at the first byte of the body. Errors are
// prefixed by `name` (the file name) and say what is wrong, e.g. "not a PLY file".
Expected<PlyHeader> ParsePlyHeader(std::istream& in, const std::string& name);

// The value of a binary scalar at `bytes` as a double (`swap`: the file is big endian).
double DecodePlyValue(const char* bytes, PlyType type, bool swap);

}  // namespace uf::exporting
