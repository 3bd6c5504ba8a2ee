// Tiny dataset files made by the tests: PCD text/binary/compressed, KITTI .bin, PNG images.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"

namespace uf::testing {

struct XyziPoint {
  float x, y, z, intensity;
};

inline void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

inline std::string PcdHeaderText(const std::string& fields, const std::string& sizes,
                                 const std::string& types, std::size_t points, const std::string& data) {
  std::string counts;
  for (std::size_t i = 0, n = std::count(fields.begin(), fields.end(), ' ') + 1; i < n; ++i)
    counts += i ? " 1" : "1";
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes +
         "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " + std::to_string(points) +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(points) + "\nDATA " + data + "\n";
}

inline std::string PackXyzi(const std::vector<XyziPoint>& points) {
  std::string bytes(points.size() * 16, '\0');
  std::memcpy(bytes.data(), points.data(), bytes.size());
  return bytes;
}

// LZF with literal runs only (a valid stream that any LZF decoder reads).
inline std::string LzfLiterals(const std::string& raw) {
  std::string out;
  for (std::size_t i = 0; i < raw.size(); i += 32) {
    const std::size_t n = std::min<std::size_t>(32, raw.size() - i);
    out += static_cast<char>(n - 1);
    out += raw.substr(i, n);
  }
  return out;
}

// x y z intensity as ascii, binary or binary_compressed (fields laid out one after another when compressed).
inline std::string XyziPcd(const std::vector<XyziPoint>& points, const std::string& data) {
  std::string text = PcdHeaderText("x y z intensity", "4 4 4 4", "F F F F", points.size(), data);
  if (data == "ascii") {
    char line[128];
    for (const XyziPoint& p : points) {
      std::snprintf(line, sizeof(line), "%.9g %.9g %.9g %.9g\n", p.x, p.y, p.z, p.intensity);
      text += line;
    }
  } else if (data == "binary") {
    text += PackXyzi(points);
  } else {
    std::string by_field;
    for (int f = 0; f < 4; ++f)
      for (const XyziPoint& p : points) by_field.append(reinterpret_cast<const char*>(&p) + 4 * f, 4);
    const std::string compressed = LzfLiterals(by_field);
    const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(compressed.size()),
                                    static_cast<std::uint32_t>(by_field.size())};
    text.append(reinterpret_cast<const char*>(sizes), 8);
    text += compressed;
  }
  return text;
}

// A PNG of a small gradient, gray or 3-channel.
inline std::string PngBytes(int width = 8, int height = 6, int channels = 1) {
  cv::Mat image(height, width, channels == 1 ? CV_8UC1 : CV_8UC3);
  for (int i = 0; i < static_cast<int>(image.total() * image.elemSize()); ++i) image.data[i] = (i * 7) & 0xff;
  std::vector<std::uint8_t> png;
  cv::imencode(".png", image, png);
  return std::string(png.begin(), png.end());
}

// `text` with the first `from` replaced by `to` (unchanged when absent).
inline std::string Replaced(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) return text;
  std::string out = text.substr(0, at);
  out += to;
  out += text.substr(at + from.size());
  return out;
}

inline const ReadWarning* FindWarning(const DatasetReader& reader, const std::string& what_contains) {
  for (const ReadWarning& warning : reader.warnings())
    if (warning.what.find(what_contains) != std::string::npos) return &warning;
  return nullptr;
}

}  // namespace uf::testing
