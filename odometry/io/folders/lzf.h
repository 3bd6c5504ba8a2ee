// LZF decompression (Marc Lehmann's liblzf format, which PCL uses for DATA binary_compressed PCD files).
// Every read and write is bounds-checked, so corrupt input only ever yields a short or failed result.
// Internal to uf_io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

namespace uf {

// Decompresses `in` into `out` (capacity out_size); the number of bytes produced, or nullopt when the data
// is corrupt (a back reference before the start, a truncated token) or would overflow `out`.
std::optional<std::size_t> LzfDecompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                                         std::size_t out_size);

}  // namespace uf
