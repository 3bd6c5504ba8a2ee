// Fuzz target of the lidar.bin record reader (the project's dataset format): any bytes give scans until an
// error or the end; never a crash, and never an allocation beyond the bytes left in the file.
#include "odometry/io/folders/lidar_record_file.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = uf::fuzz::WriteInputFile(".bin", data, size);
  auto reader = uf::LidarRecordReader::Open(path);
  if (!reader.ok()) return 0;
  while (true) {
    auto scan = reader->Next();
    if (!scan.ok() || !*scan) break;
    // A record re-encodes to the same bytes it was read from.
    if (uf::EncodeLidarRecord(**scan).size() !=
        uf::kLidarRecordHeaderBytes + (*scan)->points.size() * uf::kLidarRecordPointBytes)
      __builtin_trap();
  }
  return 0;
}
