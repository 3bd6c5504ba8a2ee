// Sensor calibration files: where each sensor sits on the body and how its clock relates to the body's.
// The simulator writes two of them (calibration_true.yaml and calibration.yaml, the latter with the injected
// errors); `colorize` reads them. Also the camera intrinsics file of `ultrafusion render --camera` (and a
// run's views/camera.yaml): one camera's intrinsics at the top level, in the same dialect as a calibration
// file's `intrinsics:` (camera_calibration.h).
//
//   calibration:
//     body_frame: imu                # the frame the trajectory and every T_body_sensor refer to
//     sensors:
//       - name: lidar                # stream name in the dataset (the topic for bags)
//         kind: lidar                # imu | lidar | camera | wheel | gnss
//         T_body_sensor: [16 numbers]   # 4x4 row-major, maps sensor-frame points into the body frame
//         time_offset_s: -0.1        # added to the sensor's stamps to put them on the body clock
//         intrinsics:                # cameras only, the keys of dataset.yaml's `calibration`
//           distortion_model: radial-tangential
//           intrinsics: [fx, fy, cx, cy]
//           distortion_coefficients: [k1, k2, p1, p2, k3]
//           resolution: [width, height]
//
// time_offset_s has the sign of `dataset.time_offsets_s`: a sensor whose stamps run 0.1 s late (stamp = true
// time + 0.1 s) has time_offset_s = -0.1. Other top-level sections are left to their own readers.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "odometry/io/measurement.h"
#include "odometry/types/camera_model.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

struct SensorCalibration {
  std::string name;
  SensorKind kind = SensorKind::kImu;
  SE3 T_body_sensor;
  Stamp time_offset = 0;                            // ns, added to the stamps
  std::shared_ptr<const CameraModel> camera_model;  // cameras only (may be null)
};

struct Calibration {
  std::string body_frame = "imu";
  std::vector<SensorCalibration> sensors;

  const SensorCalibration* Find(const std::string& name) const;
};

// Writes the file atomically; `header` is written first as '#' comment lines (one per line of the text).
Status WriteCalibrationFile(const std::filesystem::path& path, const Calibration& calibration,
                            const std::string& header = "");

// Reads the `calibration:` section. Errors name the file, the key and the value (unknown keys, missing
// fields, a transform that is not rigid, duplicate sensor names, intrinsics on a non-camera).
Expected<Calibration> ReadCalibrationFile(const std::filesystem::path& path);

// Reads a camera intrinsics file. Errors name the file, the key, its line and the value (unknown keys, a
// wrong number of values, impossible intrinsics).
Expected<std::shared_ptr<const CameraModel>> ReadCameraIntrinsicsFile(const std::filesystem::path& path);

// Writes `model` as a camera intrinsics file, atomically; `header` first as '#' comment lines.
Status WriteCameraIntrinsicsFile(const std::filesystem::path& path, const CameraModel& model,
                                 const std::string& header = "");

}  // namespace uf
