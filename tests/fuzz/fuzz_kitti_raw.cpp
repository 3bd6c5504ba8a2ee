// Fuzz target of the KITTI raw drive's file parsers: the first byte picks the parser (an OXTS record, a
// calib_*.txt, a timestamps.txt, an xz-compressed scan), the rest is the file. Any bytes give a value or an
// error; never a crash, a hang or an out-of-bounds access.
#include <cmath>

#include "odometry/io/folders/kitti_raw_files.h"
#include "odometry/io/folders/kitti_raw_oxts.h"
#include "odometry/io/folders/point_cloud_files.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::filesystem::path& path =
      uf::fuzz::WriteInputFile(data[0] % 4 == 3 ? ".bin.xz" : ".txt", data + 1, size - 1);
  switch (data[0] % 4) {
    case 0:
      if (auto record = uf::ReadOxtsFile(path); record.ok()) {
        if (!std::isfinite(record->latitude_deg) || std::abs(record->latitude_deg) > 90) __builtin_trap();
        const uf::GnssFix fix = uf::OxtsGnssFix(*record, 0);
        if (!(fix.covariance_enu(0, 0) > 0)) __builtin_trap();
      }
      break;
    case 1:
      (void)uf::ReadKittiCalibFile(path);
      break;
    case 2:
      (void)uf::ReadKittiTimestamps(path);
      break;
    case 3:
      if (auto scan = uf::ReadKittiBin(path); scan.ok())
        for (const uf::LidarPoint& p : scan->points)
          if (!std::isfinite(p.x)) __builtin_trap();
      break;
  }
  return 0;
}
