// A growing byte buffer that appends values in little-endian order, for the binary formats (PLY, LAS, glb).
// The writers fill one chunk at a time and hand it to the output stream. Assumes a little-endian host
// (checked at compile time), so a value's bytes are copied as they are.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <vector>

namespace uf::exporting {

static_assert(std::endian::native == std::endian::little, "the binary writers assume a little-endian host");

class ByteBuffer {
 public:
  template <typename T>
  void Put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    const std::size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T));
  }
  // Exactly `size` bytes: `text`, cut or padded with NUL characters.
  void PutFixedString(std::string_view text, std::size_t size) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + size, 0);
    std::memcpy(bytes_.data() + at, text.data(), std::min(size, text.size()));
  }
  void Reserve(std::size_t size) { bytes_.reserve(size); }
  void Clear() { bytes_.clear(); }
  std::size_t size() const { return bytes_.size(); }
  const char* data() const { return reinterpret_cast<const char*>(bytes_.data()); }

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace uf::exporting
