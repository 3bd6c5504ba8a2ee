// Fuzz target of the PCD reader: any bytes, read as a .pcd file, give a scan or an error; never a crash, a
// hang, an out-of-bounds access or an allocation far beyond the file's size.
#include "odometry/io/folders/point_cloud_files.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = uf::fuzz::WriteInputFile(".pcd", data, size);
  uf::PointCloudFileInfo info;
  auto scan = uf::ReadPcdFile(path, &info);
  if (scan.ok() && scan->has_point_times) {
    for (const uf::LidarPoint& point : scan->points)
      if (point.offset_ns < 0 || scan->stamp + point.offset_ns > scan->end) __builtin_trap();
  }
  return 0;
}
