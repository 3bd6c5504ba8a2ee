// Reading an xz-compressed file (liblzma) whole, for datasets stored compressed (a KITTI drive's
// velodyne_points/data/*.bin.xz). Internal to uf_io.
#pragma once

#include <filesystem>
#include <string>

#include "odometry/types/status.h"

namespace uf {

// The decompressed bytes; a damaged or truncated stream is an error naming the file. `max_bytes` bounds the
// output (a corrupt header cannot make it allocate without end).
Expected<std::string> ReadXzFile(const std::filesystem::path& path,
                                 std::size_t max_bytes = std::size_t{1} << 31);

}  // namespace uf
