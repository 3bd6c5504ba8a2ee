// Strict parser of the text header of a PCD file (PCL's Point Cloud Data format, v0.7):
//
//   # .PCD v0.7 - Point Cloud Data file format      comment lines start with '#'
//   VERSION 0.7
//   FIELDS x y z intensity                           one name per field
//   SIZE 4 4 4 4                                     bytes per value: 1, 2, 4 or 8
//   TYPE F F F F                                     I signed, U unsigned, F float (SIZE 4 or 8)
//   COUNT 1 1 1 1                                    values per field (default 1)
//   WIDTH 78238                                      points per row
//   HEIGHT 1                                         rows (default 1)
//   VIEWPOINT 0 0 0 1 0 0 0                          sensor pose tx ty tz qw qx qy qz (ignored)
//   POINTS 78238                                     = WIDTH * HEIGHT
//   DATA ascii | binary | binary_compressed          the data follows this line
//
// Every number is checked here, and the data size against them (CheckPcdDataSize), before anything is
// allocated or decoded, so a corrupt header cannot send the decoder past the end of the file or into a
// huge allocation. Internal to uf_io.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/types/status.h"

namespace uf {

enum class PcdDataKind { kAscii, kBinary, kBinaryCompressed };

struct PcdField {
  std::string name;
  int size = 4;     // bytes per value
  char type = 'F';  // 'I', 'U' or 'F'
  int count = 1;    // values per point
  int offset = 0;   // byte offset of the first value in a packed point
};

struct PcdHeader {
  std::vector<PcdField> fields;
  int point_step = 0;  // bytes per packed point: sum of size * count
  std::uint64_t width = 0, height = 1, points = 0;
  PcdDataKind data = PcdDataKind::kAscii;
  std::size_t data_offset = 0;  // bytes from the start of the file to the first data byte

  const PcdField* Find(std::string_view name) const;
  int values_per_point() const;  // sum of the counts
};

// The header must end (with its DATA line) within this many bytes.
constexpr std::size_t kMaxPcdHeaderBytes = 64 * 1024;

// Parses the header at the start of `file_start` (the first bytes of the file, at least up to the DATA line
// or kMaxPcdHeaderBytes); errors read "PATH: header line N: ...".
Expected<PcdHeader> ParsePcdHeader(std::string_view file_start, const std::string& path);

// Checks that the data after the header can hold header.points points: `data` is the whole data section
// (file bytes from data_offset to the end). Errors read "PATH: byte offset N: ...".
Status CheckPcdDataSize(const PcdHeader& header, std::string_view data, const std::string& path);

}  // namespace uf
