// Decompression of bag chunks ("bz2" through libbz2, "lz4" through roslz4, ROS's LZ4 frame codec). Both
// check the compressed stream before trusting it: output never exceeds the size the chunk header declares,
// memory grows only with the data actually produced, and a stream that is corrupt, cut off or decompresses
// to a different size is an error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "odometry/types/status.h"

namespace uf::bag {

// Decompresses `compressed` into out[0, expected_size). `out` is grown when too small and never shrunk, so a
// reader reuses one buffer for every chunk; bytes past expected_size are unspecified.
Status DecompressBz2(std::span<const std::uint8_t> compressed, std::size_t expected_size,
                     std::vector<std::uint8_t>& out);
Status DecompressLz4(std::span<const std::uint8_t> compressed, std::size_t expected_size,
                     std::vector<std::uint8_t>& out);

}  // namespace uf::bag
