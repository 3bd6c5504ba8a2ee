#include "odometry/io/folders/lzf.h"

namespace uf {

// The stream is a sequence of tokens, each starting with a control byte c:
//   c < 32:  a literal run; the next c + 1 bytes are copied as they are.
//   c >= 32: a back reference of length L = c >> 5 (when L == 7, the next byte is added to it) and distance
//            D = ((c & 31) << 8) + next byte + 1; copies L + 2 bytes starting D bytes back in the output
//            (the ranges may overlap, which repeats a pattern).
std::optional<std::size_t> LzfDecompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                                         std::size_t out_size) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned control = in[ip++];
    if (control < 32) {
      const std::size_t length = control + 1;
      if (length > in_size - ip || length > out_size - op) return std::nullopt;
      for (std::size_t i = 0; i < length; ++i) out[op++] = in[ip++];
      continue;
    }
    std::size_t length = control >> 5;
    if (length == 7) {
      if (ip >= in_size) return std::nullopt;
      length += in[ip++];
    }
    if (ip >= in_size) return std::nullopt;
    const std::size_t distance = ((control & 31u) << 8) + in[ip++] + 1;
    length += 2;
    if (distance > op || length > out_size - op) return std::nullopt;
    for (std::size_t i = 0; i < length; ++i, ++op) out[op] = out[op - distance];
  }
  return op;
}

}  // namespace uf
