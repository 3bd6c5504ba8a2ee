// One measurement of any sensor, tagged with the stream it came from: what readers produce and what the
// MeasurementStream hands to the estimator.
#pragma once

#include <optional>
#include <string_view>
#include <variant>

#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"

namespace uf {

enum class SensorKind { kImu, kLidar, kCamera, kWheel, kGnss };

// "imu", "lidar", "camera", "wheel", "gnss": the names configs and dataset files use, so they stay fixed.
std::string_view SensorKindName(SensorKind kind);
std::optional<SensorKind> ParseSensorKind(std::string_view name);  // inverse of SensorKindName

using MeasurementData = std::variant<ImuSample, LidarScan, CameraFrame, WheelSample, GnssFix>;

struct Measurement {
  int stream = 0;  // index into DatasetDescription::streams
  MeasurementData data;
};

SensorKind KindOf(const MeasurementData& data);
Stamp StampOf(const MeasurementData& data);  // the measurement time (scan start for LiDAR)

// Adds `offset` to every stamp the measurement carries (LidarScan: stamp and end; point offsets are
// relative and stay). Used to apply per-sensor time offsets.
void ShiftStamp(MeasurementData& data, Stamp offset);

}  // namespace uf
