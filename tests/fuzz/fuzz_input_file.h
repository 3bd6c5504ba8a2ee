// For fuzz targets of parsers that read files: writes each input over one scratch file per process
// (named after the process id, removed when the process exits) and returns its path.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace uf::fuzz {

inline const std::filesystem::path& WriteInputFile(const std::string& extension, const std::uint8_t* data,
                                                   std::size_t size) {
  struct ScratchFile {
    std::filesystem::path path;
    ~ScratchFile() {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  };
  static const ScratchFile file{std::filesystem::temp_directory_path() /
                                ("uf_fuzz_" + std::to_string(::getpid()) + extension)};
  std::ofstream out(file.path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file.path;
}

}  // namespace uf::fuzz
