// Names and conventions of the project's dataset format that its writer and reader share (the format is
// described in ultrafusion_dataset_writer.h). Internal to uf_io.
#pragma once

#include <charconv>
#include <string>
#include <string_view>

namespace uf::ultrafusion_format {

constexpr std::string_view kFormat = "ultrafusion-dataset";
constexpr int kVersion = 1;
constexpr std::string_view kDescriptionFile = "dataset.yaml";
constexpr std::string_view kGroundTruthFile = "groundtruth.tum";

// The shortest decimal text that reads back (std::from_chars) to exactly `value`.
inline std::string FormatNumber(double value) {
  char buffer[32];
  auto [end, error] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, error == std::errc() ? end : buffer);
}

}  // namespace uf::ultrafusion_format
