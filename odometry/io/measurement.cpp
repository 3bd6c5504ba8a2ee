#include "odometry/io/measurement.h"

#include "odometry/io/dataset_options.h"
#include "odometry/io/dataset_reader.h"

namespace uf {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;  // clang 14 lacks aggregate deduction

}  // namespace

std::string_view SensorKindName(SensorKind kind) {
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
  return "unknown";
}

std::optional<SensorKind> ParseSensorKind(std::string_view name) {
  for (SensorKind kind :
       {SensorKind::kImu, SensorKind::kLidar, SensorKind::kCamera, SensorKind::kWheel, SensorKind::kGnss}) {
    if (SensorKindName(kind) == name) return kind;
  }
  return std::nullopt;
}

std::string_view DatasetFormatName(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kAuto:
      return "auto";
    case DatasetFormat::kRosBag:
      return "rosbag";
    case DatasetFormat::kKittiFolder:
      return "kitti";
    case DatasetFormat::kKittiRaw:
      return "kitti_raw";
    case DatasetFormat::kEuroc:
      return "euroc";
    case DatasetFormat::kUltrafusion:
      return "ultrafusion";
  }
  return "unknown";
}

std::string_view PointTimeConventionName(PointTimeConvention convention) {
  switch (convention) {
    case PointTimeConvention::kNone:
      return "none";
    case PointTimeConvention::kRelativeSeconds:
      return "float32 s relative to the scan stamp";
    case PointTimeConvention::kRelativeNanoseconds:
      return "uint32 ns relative to the scan stamp";
    case PointTimeConvention::kAbsoluteSeconds:
      return "float64 s absolute";
    case PointTimeConvention::kAbsoluteNanoseconds:
      return "float64 ns absolute";
    case PointTimeConvention::kLivoxOffsetNanoseconds:
      return "uint32 ns relative to the Livox timebase";
    case PointTimeConvention::kAzimuth:
      return "derived from azimuth (no time field)";
  }
  return "unknown";
}

SensorKind KindOf(const MeasurementData& data) {
  return std::visit(Overloaded{[](const ImuSample&) { return SensorKind::kImu; },
                               [](const LidarScan&) { return SensorKind::kLidar; },
                               [](const CameraFrame&) { return SensorKind::kCamera; },
                               [](const WheelSample&) { return SensorKind::kWheel; },
                               [](const GnssFix&) { return SensorKind::kGnss; }},
                    data);
}

Stamp StampOf(const MeasurementData& data) {
  return std::visit([](const auto& m) { return m.stamp; }, data);
}

void ShiftStamp(MeasurementData& data, Stamp offset) {
  std::visit(
      [offset](auto& m) {
        m.stamp += offset;
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, LidarScan>) m.end += offset;
      },
      data);
}

}  // namespace uf
