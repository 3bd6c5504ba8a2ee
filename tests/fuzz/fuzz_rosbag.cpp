// Fuzz target of the ROS bag reader: any bytes, written to a file and opened as a bag, give measurements,
// warnings or an error; never a crash, a hang, an out-of-bounds access or an allocation far beyond the
// file's size. Scans that come out must keep their timing invariants.
#include <cstdint>
#include <variant>

#include "odometry/io/rosbag/rosbag_reader.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = uf::fuzz::WriteInputFile(".bag", data, size);
  // Half the inputs skip IMU unit detection, so damaged IMU values do not end every run at open.
  uf::DatasetOptions options;
  if (size % 2 == 1) options.imu_accel_unit = uf::ImuAccelUnit::kMetersPerSecond2;
  auto reader = uf::OpenRosBag(path, options);
  if (!reader.ok()) return 0;
  for (int i = 0; i < 10000; ++i) {  // bounded: a small input cannot hold more
    auto next = (*reader)->Next();
    if (!next.ok()) {
      if ((*reader)->Next().ok()) __builtin_trap();  // an error must stick
      break;
    }
    if (!next->has_value()) break;
    if (const auto* scan = std::get_if<uf::LidarScan>(&(*next)->data); scan && scan->has_point_times) {
      for (const uf::LidarPoint& point : scan->points) {
        if (point.offset_ns < 0 || scan->stamp + point.offset_ns > scan->end) __builtin_trap();
      }
    }
  }
  return 0;
}
