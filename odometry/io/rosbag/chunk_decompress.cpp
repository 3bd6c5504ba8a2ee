#include "odometry/io/rosbag/chunk_decompress.h"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <climits>
#include <string>

#include "odometry/io/rosbag/bag_record.h"

namespace uf::bag {
namespace {

std::string Bytes(std::size_t count) { return std::to_string(count) + " bytes"; }

void GrowTo(std::vector<std::uint8_t>& out, std::size_t size) {
  if (out.size() < size) out.resize(size);
}

// Ends the bz2 stream on every path out of DecompressBz2.
struct Bz2Stream {
  bz_stream stream{};
  bool started = false;
  ~Bz2Stream() {
    if (started) BZ2_bzDecompressEnd(&stream);
  }
};

// roslz4 writes the LZ4 frame format with one fixed layout: magic 0x184D2204, FLG = version 1, independent
// blocks, no block checksums, no content size, a content checksum, no dictionary; BD = maximum block size id
// 4..7 (64 KiB .. 4 MiB). Blocks follow as uint32 size (bit 31: stored uncompressed) + bytes, then a zero
// size and the 4-byte checksum. roslz4 copies each block into a buffer of the maximum block size without
// checking the block's size against it, so every size is checked here first. Returns the most bytes the
// frame can decompress to (LZ4 expands a byte to at most 255, so that bound stays near the input size).
Expected<std::size_t> CheckLz4Frame(std::span<const std::uint8_t> frame) {
  constexpr std::uint32_t kMagic = 0x184D2204;
  if (frame.size() < 7 || LoadLittleEndian<std::uint32_t>(frame.data()) != kMagic) {
    return Status::Error("lz4 frame does not start with the LZ4 magic number");
  }
  const std::uint8_t flags = frame[4];
  const std::uint8_t block_descriptor = frame[5];
  const int block_size_id = (block_descriptor >> 4) & 0x7;
  // Accepted: version 01, independent blocks, content checksum; everything else (block checksums, content
  // size, dictionary, reserved bits) is what roslz4 rejects too.
  if (flags != 0x64 || (block_descriptor & 0x8f) != 0 || block_size_id < 4) {
    return Status::Error("lz4 frame descriptor is not the one ROS writes (FLG " + std::to_string(flags) +
                         ", BD " + std::to_string(block_descriptor) + ")");
  }
  const std::size_t max_block = std::size_t{1} << (8 + 2 * block_size_id);
  std::size_t position = 7;
  std::size_t output_bound = 0;
  while (true) {
    if (frame.size() - position < 4) return Status::Error("lz4 frame is cut off before its end mark");
    const std::uint32_t word = LoadLittleEndian<std::uint32_t>(frame.data() + position);
    position += 4;
    if (word == 0) break;  // end mark, the content checksum follows
    const std::size_t block_size = word & 0x7fffffffu;
    const bool stored = (word >> 31) != 0;
    if (block_size > max_block) {
      return Status::Error("lz4 block of " + Bytes(block_size) + " exceeds the frame's maximum of " +
                           Bytes(max_block));
    }
    if (block_size > frame.size() - position) return Status::Error("lz4 block is cut off");
    position += block_size;
    output_bound += stored ? block_size : std::min(max_block, 255 * block_size + 64);
  }
  if (frame.size() - position != 4) {
    return Status::Error("lz4 frame has " + Bytes(frame.size() - position) +
                         " after its end mark, expected 4");
  }
  return output_bound;
}

}  // namespace

Status DecompressBz2(std::span<const std::uint8_t> compressed, std::size_t expected_size,
                     std::vector<std::uint8_t>& out) {
  if (compressed.size() > UINT_MAX) return Status::Error("bz2 chunk larger than 4 GiB");
  Bz2Stream bz2;
  if (BZ2_bzDecompressInit(&bz2.stream, 0, 0) != BZ_OK) return Status::Error("bz2 decoder did not start");
  bz2.started = true;
  bz2.stream.next_in = const_cast<char*>(reinterpret_cast<const char*>(compressed.data()));
  bz2.stream.avail_in = static_cast<unsigned int>(compressed.size());
  // Room for one byte more than declared, to notice a stream that decompresses to more. Grown by doubling
  // from a guess, so a corrupt size field cannot make us allocate memory the data never fills.
  const std::size_t limit = expected_size + 1;
  std::size_t room = std::min(limit, std::max<std::size_t>(std::size_t{1} << 16, 4 * compressed.size()));
  GrowTo(out, room);
  std::size_t produced = 0;
  while (true) {
    const std::size_t step = std::min<std::size_t>(room - produced, UINT_MAX);
    bz2.stream.next_out = reinterpret_cast<char*>(out.data() + produced);
    bz2.stream.avail_out = static_cast<unsigned int>(step);
    const unsigned int input_before = bz2.stream.avail_in;
    const int result = BZ2_bzDecompress(&bz2.stream);
    produced += step - bz2.stream.avail_out;
    if (result == BZ_STREAM_END) break;
    if (result != BZ_OK) {
      return Status::Error("bz2 data is corrupt (libbz2 error " + std::to_string(result) + ")");
    }
    if (produced > expected_size) {
      return Status::Error("bz2 chunk decompresses to more than the declared " + Bytes(expected_size));
    }
    if (bz2.stream.avail_out > 0 && bz2.stream.avail_in == 0 && input_before == 0) {
      return Status::Error("bz2 stream is cut off after " + Bytes(produced));
    }
    if (produced == room) {
      room = std::min(limit, 2 * room);
      GrowTo(out, room);
    }
  }
  if (produced != expected_size) {
    return Status::Error("bz2 chunk decompresses to " + Bytes(produced) + ", its header declares " +
                         Bytes(expected_size));
  }
  return Status();
}

Status DecompressLz4(std::span<const std::uint8_t> compressed, std::size_t expected_size,
                     std::vector<std::uint8_t>& out) {
  if (compressed.size() > INT_MAX || expected_size > INT_MAX) {
    return Status::Error("lz4 chunk larger than 2 GiB");
  }
  const Expected<std::size_t> bound = CheckLz4Frame(compressed);
  if (!bound.ok()) return bound.status();
  if (expected_size > *bound) {
    return Status::Error("lz4 chunk declares " + Bytes(expected_size) + ", more than its frame can hold (" +
                         Bytes(*bound) + ")");
  }
  GrowTo(out, std::max<std::size_t>(expected_size, 1));
  unsigned int produced = static_cast<unsigned int>(expected_size);
  const int result = roslz4_buffToBuffDecompress(
      const_cast<char*>(reinterpret_cast<const char*>(compressed.data())),
      static_cast<unsigned int>(compressed.size()), reinterpret_cast<char*>(out.data()), &produced);
  if (result != ROSLZ4_OK) {
    return Status::Error("lz4 data is corrupt or larger than the declared " + Bytes(expected_size) +
                         " (roslz4 error " + std::to_string(result) + ")");
  }
  if (produced != expected_size) {
    return Status::Error("lz4 chunk decompresses to " + Bytes(produced) + ", its header declares " +
                         Bytes(expected_size));
  }
  return Status();
}

}  // namespace uf::bag
