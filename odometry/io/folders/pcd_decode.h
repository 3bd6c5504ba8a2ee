// Turns the (validated, decompressed) body of a PCD file into a LidarScan: picks the x y z, intensity, ring
// and per-point time fields and converts their values. Internal to uf_io.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/io/folders/pcd_header.h"
#include "odometry/io/folders/point_cloud_files.h"

namespace uf {

// Where the values of each field lie in a body: value c of field f of point i starts at
// base[f] + i * stride[f] + c * size.
struct PcdLayout {
  std::vector<std::uint64_t> base;
  std::vector<std::uint64_t> stride;

  static PcdLayout PointMajor(const PcdHeader& header);  // DATA ascii (once packed) and binary
  static PcdLayout FieldMajor(const PcdHeader& header);  // DATA binary_compressed (once decompressed)
};

// `body` must hold header.points points in `layout` (CheckPcdDataSize / decompression ensure it).
Expected<LidarScan> DecodePcdPoints(const PcdHeader& header, const PcdLayout& layout, std::string_view body,
                                    const std::string& path, PointCloudFileInfo* info);

}  // namespace uf
