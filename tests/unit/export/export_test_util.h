// Helpers shared by the export tests: a scratch folder removed at the end, deterministic synthetic maps,
// little-endian field reads for the independent file parsers.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mapping/map_point.h"

namespace uf::exporting::test {

class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "uf_export_XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Names of everything in the folder (to see that no temporary file is left behind).
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(path_))
      names.push_back(e.path().filename().string());
    return names;
  }

 private:
  std::filesystem::path path_;
};

// `n` points spread over a `extent` m cube centred on `center`, every field varied: colours (every 5th
// point uncoloured), intensity, unit normals, counts, stamps. Deterministic in `seed`.
inline std::vector<mapping::MapPoint> MakePoints(std::size_t n, const Eigen::Vector3d& center, double extent,
                                                 std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<mapping::MapPoint> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    mapping::MapPoint& p = points[i];
    p.position = center + extent * Eigen::Vector3d(u(rng), u(rng), u(rng));
    p.normal = Eigen::Vector3f(float(u(rng)), float(u(rng)), 1.0f).normalized();
    p.has_color = i % 5 != 0;
    p.rgb = {std::uint8_t(rng() & 255), std::uint8_t(rng() & 255), std::uint8_t(rng() & 255)};
    p.intensity = float(rng() % 256);
    p.count = std::uint32_t(1 + rng() % 400);
    p.last_stamp = 1'700'000'000'000'000'000 + std::int64_t(i) * 1'000'003;
  }
  return points;
}

inline std::vector<std::uint8_t> ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A little-endian value at byte `offset` (the host is little-endian, as the writers assume).
template <typename T>
T At(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  EXPECT_LE(offset + sizeof(T), bytes.size());
  T value{};
  if (offset + sizeof(T) <= bytes.size()) std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

inline std::string StringAt(const std::vector<std::uint8_t>& bytes, std::size_t offset, std::size_t size) {
  std::string s(reinterpret_cast<const char*>(bytes.data()) + offset, size);
  return s.substr(0, s.find('\0'));
}

}  // namespace uf::exporting::test
