// The LiDAR file of the project's dataset format (`lidar.bin`): scan records appended one after another,
// no file header. Every number is little-endian.
//
//   offset  bytes  field
//   0       4      magic "UFLS" (0x55 0x46 0x4C 0x53)
//   4       4      flags, uint32: bit 0 has_point_times, bit 1 point_times_from_azimuth, bit 2 has_ring;
//                  the other bits are 0
//   8       8      stamp_ns, int64: scan start
//   16      8      end_ns, int64: scan end, >= stamp_ns
//   24      8      point_count, uint64
//   32      22 * point_count, per point:
//                    x, y, z, intensity   float32 each (m, m, m, sensor units), lidar frame
//                    ring                 uint16
//                    offset_ns            int32, point time minus stamp_ns
//
// The reader holds one record at a time and checks point_count against the bytes left in the file before
// allocating, so a corrupt count cannot ask for gigabytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf {

constexpr std::size_t kLidarRecordHeaderBytes = 32;
constexpr std::size_t kLidarRecordPointBytes = 22;

// The bytes of one record.
std::string EncodeLidarRecord(const LidarScan& scan);

class LidarRecordReader {
 public:
  static Expected<LidarRecordReader> Open(const std::filesystem::path& path);

  // The next scan, nullopt at the end of the file. Errors read "PATH: byte offset N: ...".
  Expected<std::optional<LidarScan>> Next();

  std::uint64_t offset() const { return offset_; }  // of the next record

 private:
  Status Error(std::uint64_t offset, const std::string& what) const;

  std::string path_;
  std::unique_ptr<std::ifstream> in_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
};

}  // namespace uf
