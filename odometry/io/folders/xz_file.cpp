#include "odometry/io/folders/xz_file.h"

#include <lzma.h>

#include <fstream>
#include <vector>

namespace uf {

Expected<std::string> ReadXzFile(const std::filesystem::path& path, std::size_t max_bytes) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(name + ": cannot open file");
  lzma_stream stream = LZMA_STREAM_INIT;
  if (lzma_stream_decoder(&stream, UINT64_MAX, LZMA_CONCATENATED) != LZMA_OK)
    return Status::Error(name + ": cannot start the xz decoder");
  std::vector<std::uint8_t> input(1 << 16);
  std::string output;
  std::uint8_t chunk[1 << 16];
  lzma_action action = LZMA_RUN;
  lzma_ret result = LZMA_OK;
  while (result == LZMA_OK) {
    if (stream.avail_in == 0 && action == LZMA_RUN) {
      in.read(reinterpret_cast<char*>(input.data()), static_cast<std::streamsize>(input.size()));
      stream.next_in = input.data();
      stream.avail_in = static_cast<std::size_t>(in.gcount());
      if (in.bad()) break;
      if (!in) action = LZMA_FINISH;  // end of file: LZMA_CONCATENATED needs to be told
    }
    stream.next_out = chunk;
    stream.avail_out = sizeof(chunk);
    result = lzma_code(&stream, action);
    output.append(reinterpret_cast<const char*>(chunk), sizeof(chunk) - stream.avail_out);
    if (output.size() > max_bytes) {
      lzma_end(&stream);
      return Status::Error(name + ": decompresses to more than " + std::to_string(max_bytes) + " bytes");
    }
  }
  lzma_end(&stream);
  if (in.bad()) return Status::Error(name + ": read error");
  if (result != LZMA_STREAM_END)
    return Status::Error(name + ": damaged xz data (" +
                         (result == LZMA_BUF_ERROR      ? std::string("truncated")
                          : result == LZMA_FORMAT_ERROR ? std::string("not an xz file")
                                                        : "liblzma error " + std::to_string(result)) +
                         ")");
  return output;
}

}  // namespace uf
