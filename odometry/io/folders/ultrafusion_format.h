// Names and conventions of the project's dataset format that its writer and reader share (the format is
// described in ultrafusion_dataset_writer.h). Internal to uf_io.
#pragma once

#include <charconv>
#include <optional>
#include <string>
#include <string_view>

#include "odometry/io/measurement.h"

namespace uf::ultrafusion_format {

constexpr std::string_view kFormat = "ultrafusion-dataset";
constexpr int kVersion = 1;
constexpr std::string_view kDescriptionFile = "dataset.yaml";
constexpr std::string_view kGroundTruthFile = "groundtruth.tum";

// The kind names of dataset.yaml; fixed here so the file format does not follow renames elsewhere.
inline std::string_view KindName(SensorKind kind) {
  switch (kind) {
    case SensorKind::kImu:
      return "imu";
    case SensorKind::kLidar:
      return "lidar";
    case SensorKind::kCamera:
      return "camera";
    case SensorKind::kWheel:
      return "wheel";
    case SensorKind::kGnss:
      return "gnss";
  }
  return "?";
}

inline std::optional<SensorKind> ParseKind(std::string_view name) {
  for (SensorKind kind :
       {SensorKind::kImu, SensorKind::kLidar, SensorKind::kCamera, SensorKind::kWheel, SensorKind::kGnss})
    if (KindName(kind) == name) return kind;
  return std::nullopt;
}

// The shortest decimal text that reads back (std::from_chars) to exactly `value`.
inline std::string FormatNumber(double value) {
  char buffer[32];
  auto [end, error] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, error == std::errc() ? end : buffer);
}

}  // namespace uf::ultrafusion_format
